#include "analysis/answers.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "analysis/subset_replay.hpp"
#include "designs/design_rules.hpp"

namespace treedyn::ensemble {
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

RankSensitivity ranks_of(const EnsembleSpec& spec, const ResponseTable& table, std::size_t r) {
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

// Indices per Saltelli unit (an input, or a group of them), from the
// complete blocks among the first `base_points`: a block counts only when
// all its U + 2 runs succeeded with finite values.
SobolIndices sobol_of(const EnsembleSpec& spec, const ResponseTable& table, std::size_t r, std::uint64_t base_points) {
  const std::size_t d = spec.unit_count(), block = spec.saltelli_block();
  std::vector<double> f_a, f_b, f_ab;
  for (std::uint64_t j = 0; j < base_points; ++j) {
    bool complete = true;
    for (std::size_t m = 0; m < block; ++m) {
      const std::uint64_t k = j * block + m;
      complete = complete && table.ok(k) && std::isfinite(table.response(k, r));
    }
    if (!complete) continue;
    f_a.push_back(table.response(j * block, r));
    f_b.push_back(table.response(j * block + 1, r));
    for (std::size_t i = 0; i < d; ++i) f_ab.push_back(table.response(j * block + 2 + i, r));
  }
  return saltelli_indices(f_a, f_b, f_ab, d, spec.bootstrap_resamples, spec.seed);
}

// The indices, and their convergence on the first 1, 2, 4, ... base points
// (a prefix of whole blocks is a Saltelli design of its own).
void answer_sobol(const EnsembleSpec& spec, const ResponseTable& table, std::size_t r, ResponseAnswer& a) {
  const std::uint64_t blocks = table.samples() / spec.saltelli_block();
  a.sobol_blocks = blocks;
  a.sobol = sobol_of(spec, table, r, blocks);
  // From 4 base points: with 1 or 2 the bootstrap has nothing to resample.
  for (std::uint64_t m = 4; m < blocks; m *= 2) a.sobol_convergence.push_back({m, sobol_of(spec, table, r, m)});
  if (blocks > 0) a.sobol_convergence.push_back({blocks, *a.sobol});
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
// steps of the design (saltelli: whole blocks, 2 independent draws each;
// morris: trajectories, 1 each) and the failed and infinite ones in `a`.
// The mean, the standard error, the exceedance (and their intervals), the
// rank measures and the failure region use the independent draws only.
DrawCounts count_draws(const EnsembleSpec& spec, const ResponseTable& table, std::size_t r, std::uint64_t n,
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
void answer_sensitivity(const EnsembleSpec& spec, const ResponseTable& table, std::size_t r, std::uint64_t n,
                        ResponseAnswer& a) {
  if (table.input_count() > 0) a.ranks = ranks_of(spec, table, r);
  if (spec.design == Design::saltelli) answer_sobol(spec, table, r, a);
  if (spec.design == Design::morris)
    a.morris = designs::morris_indices(designs::elementary_effects(spec, table, r), spec.unit_count(),
                                       spec.bootstrap_resamples, spec.seed);
  // Subset simulation's response has its failure region in its answer
  // (answer_rare_event): level 0 alone rarely reaches the limit.
  const bool subset_answer = spec.subset && spec.subset->response == r;
  if (spec.responses[r].has_limit() && table.input_count() > 0 && !subset_answer) {
    const designs::DesignRules& rules = designs::rules_of(spec.design);
    a.failure_region =
        failure_region(spec, table, r, [&](std::uint64_t k) { return k < n && rules.independent_draw(spec, k); });
  }
}

}  // namespace

ResponseAnswer answer_response(const EnsembleSpec& spec, const ResponseTable& table, std::size_t r,
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

IndexVerdict index_verdict(const SobolIndices& s) {
  IndexVerdict v;
  v.widest = std::numeric_limits<double>::quiet_NaN();
  v.needed = v.widest;
  const std::vector<std::size_t>& order = s.ranking.order;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::size_t u = order[k];
    if (k > 0 && !(s.total[u] >= kIndexMatters)) break;
    // Within [0, 1], as shown: an index cannot leave it, so the part of an
    // interval beyond it says nothing.
    const double width = std::min(s.total_ci[2 * u + 1], 1.0) - std::max(s.total_ci[2 * u], 0.0);
    if (std::isnan(width)) return v;  // no intervals: no verdict
    if (k == 0 || width > v.widest) v.widest = width, v.unit = u;
  }
  if (std::isnan(v.widest)) return v;
  v.enough = v.widest <= kIndexIntervalWidth;
  const double ratio = v.widest / kIndexIntervalWidth;
  v.needed = std::ceil(static_cast<double>(s.base_samples) * ratio * ratio);
  return v;
}

RareEventAnswer answer_rare_event(const EnsembleSpec& spec, const ResponseTable& table) {
  RareEventAnswer answer{replay_subset(spec, table, spec.subset->max_levels).result(), {}};
  // The runs beyond the limit are mostly the last level's chain states.
  const double gamma = answer.result.levels.empty() ? 0.0 : answer.result.levels.back().gamma;
  answer.region = failure_region(
      spec, table, spec.subset->response, [](std::uint64_t) { return true; }, std::isfinite(gamma) ? gamma : 0.0);
  return answer;
}

std::vector<ResponseAnswer> answer_responses(const EnsembleSpec& spec, const ResponseTable& table) {
  if (spec.subset && table.samples() > spec.samples) {
    ResponseTable level_zero = table;
    level_zero.truncate(spec.samples);
    return answer_responses(spec, level_zero);
  }
  if (table.input_count() != spec.input_dimensions())
    throw std::invalid_argument("answers: the table's inputs are not the ensemble's");
  std::vector<ResponseAnswer> answers;
  for (std::size_t r = 0; r < spec.responses.size(); ++r)
    answers.push_back(answer_response(spec, table, r, table.samples(), true));
  return answers;
}

}  // namespace treedyn::ensemble
