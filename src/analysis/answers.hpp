// The answers an analyst asks of an ensemble, computed on one rank from the
// per-sample records in sample-index order (so they do not depend on the
// number of ranks): each response's mean and standard error, the
// probability that it exceeds its limit, how both converge with the number
// of samples, and which inputs drive it.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <ostream>
#include <vector>

#include "analysis/failure_region.hpp"
#include "analysis/sensitivity.hpp"
#include "designs/design_answer.hpp"
#include "ensemble/response_table.hpp"
#include "job/ensemble_spec.hpp"
#include "statistics/tolerance_check.hpp"

namespace treedyn::analysis {

// Wilson's score interval for k successes in n trials at normal quantile z:
// centre (p + z^2 / 2n) / (1 + z^2 / n), half width
// z / (1 + z^2 / n) sqrt(p (1 - p) / n + z^2 / 4n^2), p = k / n.
struct Interval {
  double low = 0.0, high = 0.0;
};
Interval wilson_interval(std::uint64_t k, std::uint64_t n, double z = kZ95);

struct Exceedance {
  std::uint64_t exceeded = 0;    // successful samples beyond the limit
  std::uint64_t successful = 0;  // the denominator
  std::uint64_t failed = 0;      // samples left out (integration failed, invalid model)
  double probability = 0.0;      // exceeded / successful (NaN when none succeeded)
  Interval interval;             // 95 % Wilson
  // P over successful + failed with every failed sample counted as not
  // exceeding (low) and as exceeding (high): what the failures can change.
  Interval with_failed;
};

// One row per sample count m = 1, 2, 4, ..., and N, in the design's steps
// (DesignRules::runs_per_step: e.g. Saltelli's blocks of U + 2): the
// answers from samples 0 .. m-1.
struct ConvergencePoint {
  std::uint64_t samples = 0;  // m
  std::uint64_t used = 0;     // successful with a finite value
  double mean = 0.0, sem = 0.0;
  double probability = 0.0;  // of exceeding the limit (NaN without a limit)
  Interval interval;
};

// The counts, mean, standard error and exceedance use the design's
// independent draws only (DesignRules::independent_draw: e.g. Saltelli's A
// and B runs, not its AB_i rows); the design's own answer uses every run.
struct ResponseAnswer {
  std::uint64_t used = 0;        // successful samples with a finite value (in mean, std, sem)
  std::uint64_t not_finite = 0;  // successful samples with +-inf (e.g. a level never crossed)
  std::uint64_t failed = 0;
  double mean = 0.0, std = 0.0, sem = 0.0;  // std: n - 1; sem = std / sqrt(used)
  std::optional<Exceedance> exceedance;
  std::vector<ConvergencePoint> convergence;
  RankSensitivity ranks;                        // needs inputs (empty without perturbations)
  std::optional<FailureRegion> failure_region;  // with a limit and inputs: of the counted runs
  // The design's own answer (designs/design_answer.hpp: Saltelli's Sobol'
  // indices, Morris' effects), or none.
  std::shared_ptr<const designs::DesignAnswer> design;
};

// The design's own answer as what it is (e.g. designs::SaltelliAnswer), or
// null when it is none or another design's.
template <class Answer>
const Answer* design_answer_as(const ResponseAnswer& a) {
  return dynamic_cast<const Answer*>(a.design.get());
}

// The answers for response r from samples 0 .. prefix-1 of `table`; the
// rank measures and Sobol' indices only `with_sensitivity`.
ResponseAnswer answer_response(const EnsembleSpec& spec, const ensemble::ResponseTable& table, std::size_t r,
                               std::uint64_t prefix, bool with_sensitivity);

// The answers for every response of `spec`, from `table`: every sample,
// but for subset simulation level 0 alone (its later levels' runs are
// conditional samples, not a Monte-Carlo sample).
std::vector<ResponseAnswer> answer_responses(const EnsembleSpec& spec, const ensemble::ResponseTable& table);

// The end-of-run lines: each response's mean +- standard error, and each
// exceedance probability with its interval (answer_summary.cpp).
// With `tolerance`, each response's line on the integration's accuracy.
void print_response_summary(std::ostream& out, const EnsembleSpec& spec, const std::vector<ResponseAnswer>& answers,
                            const statistics::ToleranceCheck& tolerance = {});

}  // namespace treedyn::analysis
