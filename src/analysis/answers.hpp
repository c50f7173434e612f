// The answers an analyst asks of an ensemble, computed on one rank from the
// per-sample records in sample-index order (so they do not depend on the
// number of ranks): each response's mean and standard error, the
// probability that it exceeds its limit, how both converge with the number
// of samples, and which inputs drive it.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <vector>

#include "analysis/failure_region.hpp"
#include "analysis/sensitivity.hpp"
#include "designs/morris/morris_effects.hpp"
#include "ensemble/response_table.hpp"
#include "job/ensemble_spec.hpp"
#include "rare_event/subset_simulation.hpp"
#include "statistics/tolerance_check.hpp"

namespace treedyn::ensemble {

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

// One row per sample count m = 1, 2, 4, ..., and N (saltelli: m = (U + 2)
// times 1, 2, 4, ... blocks, and N): the answers from samples 0 .. m-1.
struct ConvergencePoint {
  std::uint64_t samples = 0;  // m
  std::uint64_t used = 0;     // successful with a finite value
  double mean = 0.0, sem = 0.0;
  double probability = 0.0;  // of exceeding the limit (NaN without a limit)
  Interval interval;
};

// The Sobol' indices of the first `base_points` base points (their complete
// blocks: indices.base_samples of them).
struct SobolPrefix {
  std::uint64_t base_points = 0;
  SobolIndices indices;
};

// "Is N enough for the indices?": the widest 95 % interval (within [0, 1])
// of a total index among the units that matter (total index >= kIndexMatters, and at least
// the largest), enough when within kIndexIntervalWidth; `needed` is about
// the base points that would make it so, N (widest / kIndexIntervalWidth)^2.
inline constexpr double kIndexMatters = 0.05;
inline constexpr double kIndexIntervalWidth = 0.1;
// Indices resting on fewer than this share of the blocks run are unreliable:
// the failed runs' blocks are left out, and failures that depend on the
// inputs bias what remains.
inline constexpr double kReliableBlockShare = 0.8;
struct IndexVerdict {
  double widest = 0.0;   // NaN without intervals
  std::size_t unit = 0;  // whose interval it is
  double needed = 0.0;   // base points
  bool enough = false;
};
IndexVerdict index_verdict(const SobolIndices& s);

// For design = "saltelli" the counts, mean, standard error and exceedance
// use the A and B runs only (the AB_i rows are not independent draws); the
// Sobol' indices use every run. For design = "morris" they use each
// trajectory's first run (independent draws of the inputs' level grid);
// the effects use every run.
struct ResponseAnswer {
  std::uint64_t used = 0;        // successful samples with a finite value (in mean, std, sem)
  std::uint64_t not_finite = 0;  // successful samples with +-inf (e.g. a level never crossed)
  std::uint64_t failed = 0;
  double mean = 0.0, std = 0.0, sem = 0.0;  // std: n - 1; sem = std / sqrt(used)
  std::optional<Exceedance> exceedance;
  std::vector<ConvergencePoint> convergence;
  RankSensitivity ranks;                         // needs inputs (empty without perturbations)
  std::optional<SobolIndices> sobol;             // design = "saltelli" only
  std::uint64_t sobol_blocks = 0;                // base points run; sobol->base_samples of them complete
  std::vector<SobolPrefix> sobol_convergence;    // on 1, 2, 4, ... base points, and all
  std::optional<FailureRegion> failure_region;   // with a limit and inputs: of the counted runs
  std::optional<designs::MorrisIndices> morris;  // design = "morris" only
};

// The answers for response r from samples 0 .. prefix-1 of `table`; the
// rank measures and Sobol' indices only `with_sensitivity`.
ResponseAnswer answer_response(const EnsembleSpec& spec, const ResponseTable& table, std::size_t r,
                               std::uint64_t prefix, bool with_sensitivity);

// The answers for every response of `spec`, from `table`: every sample,
// but for subset simulation level 0 alone (its later levels' runs are
// conditional samples, not a Monte-Carlo sample).
std::vector<ResponseAnswer> answer_responses(const EnsembleSpec& spec, const ResponseTable& table);

// The end-of-run lines: each response's mean +- standard error, and each
// exceedance probability with its interval (answer_summary.cpp).
// With `tolerance`, each response's line on the integration's accuracy.
void print_response_summary(std::ostream& out, const EnsembleSpec& spec, const std::vector<ResponseAnswer>& answers,
                            const ToleranceCheck& tolerance = {});

// Subset simulation's answer: its levels' result, and the failure region of
// every run beyond the limit (any level: each is a draw of the inputs given
// the failure).
struct RareEventAnswer {
  rare_event::SubsetResult result;
  FailureRegion region;
};
RareEventAnswer answer_rare_event(const EnsembleSpec& spec, const ResponseTable& table);

// Subset simulation's answer: P(limit exceeded) with its coefficient of
// variation and interval, each level's threshold, the runs made, what
// crude Monte Carlo would have needed for the same coefficient of
// variation, and what makes it fail.
void print_rare_event(std::ostream& out, const EnsembleSpec& spec, const RareEventAnswer& answer);

}  // namespace treedyn::ensemble
