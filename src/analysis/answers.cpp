#include "analysis/answers.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "designs/design_rules.hpp"
#include "designs/registry_analysis.hpp"

namespace treedyn::analysis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Welford's running mean and sum of squared deviations, in sample order.
struct Running {
  std::uint64_t n = 0;
  double mean = 0.0, m2 = 0.0;
  void add(double x) {
    ++n;
    const double delta = x - mean;
    mean += delta / static_cast<double>(n);
    m2 += delta * (x - mean);
  }
  double std_dev() const { return n > 1 ? std::sqrt(m2 / static_cast<double>(n - 1)) : kNaN; }
  double sem() const { return n > 1 ? std_dev() / std::sqrt(static_cast<double>(n)) : kNaN; }
};

double ratio(std::uint64_t k, std::uint64_t n) {
  return n > 0 ? static_cast<double>(k) / static_cast<double>(n) : kNaN;
}

RankSensitivity ranks_of(const EnsembleSpec& spec, const ensemble::ResponseTable& table, std::size_t r) {
  const std::size_t d = table.input_count();
  const designs::DesignRules& rules = designs::rules_of(spec.design);
  std::vector<double> x, y;
  x.reserve(table.samples() * d);
  y.reserve(table.samples());
  for (std::uint64_t k = 0; k < table.samples(); ++k) {
    if (!table.ok(k) || std::isnan(table.response(k, r)) || !rules.independent_draw(spec, k)) continue;
    for (std::size_t i = 0; i < d; ++i) x.push_back(table.input(k, i));
    y.push_back(table.response(k, r));
  }
  return rank_sensitivity(x, d, y, spec.bootstrap_resamples, spec.seed);
}

// P over successful + failed samples, every failed one counted as not
// exceeding and as exceeding.
Interval with_failed(std::uint64_t exceeded, std::uint64_t successful, std::uint64_t failed) {
  const std::uint64_t all = successful + failed;
  return {ratio(exceeded, all), ratio(exceeded + failed, all)};
}

}  // namespace

Interval wilson_interval(std::uint64_t k, std::uint64_t n, double z) {
  if (n == 0) return {kNaN, kNaN};
  const double nn = static_cast<double>(n), p = static_cast<double>(k) / nn, z2 = z * z;
  const double denominator = 1.0 + z2 / nn;
  const double centre = (p + z2 / (2.0 * nn)) / denominator;
  const double half = z / denominator * std::sqrt(p * (1.0 - p) / nn + z2 / (4.0 * nn * nn));
  // Exactly 0 for k = 0 and 1 for k = n (rounding would leave them a hair inside).
  return {k == 0 ? 0.0 : std::max(0.0, centre - half), k == n ? 1.0 : std::min(1.0, centre + half)};
}

namespace {

// What the independent draws among runs 0 .. n-1 give response r.
struct DrawCounts {
  Running running;  // over the successful draws with a finite value
  std::uint64_t successful = 0, exceeded = 0;
};

// The draws in run order, with the convergence points at 1, 2, 4, ...
// steps of the design (DesignRules::runs_per_step) and the failed and
// infinite ones in `a`.
// The mean, the standard error, the exceedance (and their intervals), the
// rank measures and the failure region use the independent draws only.
DrawCounts count_draws(const EnsembleSpec& spec, const ensemble::ResponseTable& table, std::size_t r, std::uint64_t n,
                       ResponseAnswer& a) {
  const Response& response = spec.responses[r];
  const designs::DesignRules& rules = designs::rules_of(spec.design);
  DrawCounts c;
  std::uint64_t next_report = rules.runs_per_step(spec);
  for (std::uint64_t k = 0; k < n; ++k) {
    if (!rules.independent_draw(spec, k)) {
      // e.g. Saltelli's AB_i rows, which repeat all of A_j's inputs but one
    } else if (!table.ok(k)) {
      ++a.failed;
    } else {
      ++c.successful;
      const double v = table.response(k, r);
      if (std::isfinite(v))
        c.running.add(v);
      else
        ++a.not_finite;
      if (response.exceeds(v)) ++c.exceeded;
    }
    const std::uint64_t m = k + 1;
    if (m == next_report || m == n) {
      ConvergencePoint p;
      p.samples = m;
      p.used = c.running.n;
      p.mean = c.running.n > 0 ? c.running.mean : kNaN;
      p.sem = c.running.sem();
      p.probability = response.has_limit() ? ratio(c.exceeded, c.successful) : kNaN;
      p.interval = response.has_limit() ? wilson_interval(c.exceeded, c.successful) : Interval{kNaN, kNaN};
      a.convergence.push_back(p);
      while (next_report <= m) next_report *= 2;
    }
  }
  return c;
}

// Which inputs drive response r: the rank measures, the design's own
// indices (Saltelli's Sobol', Morris' effects) and the failure region.
void answer_sensitivity(const EnsembleSpec& spec, const ensemble::ResponseTable& table, std::size_t r, std::uint64_t n,
                        ResponseAnswer& a) {
  if (table.input_count() > 0) a.ranks = ranks_of(spec, table, r);
  a.design = designs::design_answer(spec, table, r);
  const designs::DesignRules& rules = designs::rules_of(spec.design);
  if (spec.responses[r].has_limit() && table.input_count() > 0 && !rules.answers_probability(spec, r)) {
    a.failure_region =
        failure_region(spec, table, r, [&](std::uint64_t k) { return k < n && rules.independent_draw(spec, k); });
  }
}

}  // namespace

ResponseAnswer answer_response(const EnsembleSpec& spec, const ensemble::ResponseTable& table, std::size_t r,
                               std::uint64_t prefix, bool with_sensitivity) {
  const std::uint64_t n = std::min(prefix, table.samples());
  ResponseAnswer a;
  const DrawCounts c = count_draws(spec, table, r, n, a);
  a.used = c.running.n;
  a.mean = c.running.n > 0 ? c.running.mean : kNaN;
  a.std = c.running.std_dev();
  a.sem = c.running.sem();
  if (spec.responses[r].has_limit()) {
    Exceedance e;
    e.exceeded = c.exceeded;
    e.successful = c.successful;
    e.failed = a.failed;
    e.probability = ratio(c.exceeded, c.successful);
    e.interval = wilson_interval(c.exceeded, c.successful);
    e.with_failed = with_failed(c.exceeded, c.successful, a.failed);
    a.exceedance = e;
  }
  if (with_sensitivity) answer_sensitivity(spec, table, r, n, a);
  return a;
}

std::vector<ResponseAnswer> answer_responses(const EnsembleSpec& spec, const ensemble::ResponseTable& table) {
  if (const std::uint64_t n = designs::rules_of(spec.design).answered_runs(spec, table.samples());
      n < table.samples()) {
    ensemble::ResponseTable answered = table;
    answered.truncate(n);
    return answer_responses(spec, answered);
  }
  if (table.input_count() != spec.input_dimensions())
    throw std::invalid_argument("answers: the table's inputs are not the ensemble's");
  std::vector<ResponseAnswer> answers;
  for (std::size_t r = 0; r < spec.responses.size(); ++r)
    answers.push_back(answer_response(spec, table, r, table.samples(), true));
  return answers;
}

}  // namespace treedyn::analysis
