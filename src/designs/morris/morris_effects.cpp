#include "designs/morris/morris_effects.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "designs/morris/morris_answer.hpp"
#include "designs/morris/morris_points.hpp"
#include "designs/sample_design.hpp"
#include "sampling/design.hpp"

namespace treedyn::designs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Stream of counter_uniform for the trajectories' bootstrap.
constexpr std::uint64_t kTrajectoryBootstrapStream = 11;

struct Measures {
  std::vector<double> mu, mu_star, sigma;
  std::vector<std::uint64_t> count;
};

// mu, mu* and sigma per unit over the trajectories `rows` (repeats allowed).
Measures measures(std::span<const double> effects, std::size_t units, std::span<const std::size_t> rows) {
  Measures m{std::vector<double>(units, 0.0), std::vector<double>(units, 0.0), std::vector<double>(units, 0.0),
             std::vector<std::uint64_t>(units, 0)};
  for (std::size_t t : rows)
    for (std::size_t g = 0; g < units; ++g) {
      const double e = effects[t * units + g];
      if (std::isnan(e)) continue;
      ++m.count[g];
      m.mu[g] += e;
      m.mu_star[g] += std::abs(e);
    }
  for (std::size_t g = 0; g < units; ++g) {
    const auto n = static_cast<double>(m.count[g]);
    m.mu[g] = m.count[g] > 0 ? m.mu[g] / n : kNaN;
    m.mu_star[g] = m.count[g] > 0 ? m.mu_star[g] / n : kNaN;
  }
  for (std::size_t t : rows)  // two passes: no cancellation in the spread
    for (std::size_t g = 0; g < units; ++g)
      if (const double e = effects[t * units + g]; !std::isnan(e)) m.sigma[g] += (e - m.mu[g]) * (e - m.mu[g]);
  for (std::size_t g = 0; g < units; ++g)
    m.sigma[g] = m.count[g] > 1 ? std::sqrt(m.sigma[g] / static_cast<double>(m.count[g] - 1)) : kNaN;
  return m;
}

}  // namespace

MorrisIndices morris_indices(std::span<const double> effects, std::size_t units, int resamples, std::uint64_t seed) {
  if (units == 0 || effects.size() % units != 0)
    throw std::invalid_argument("morris_indices: effects are not trajectories x units");
  const std::size_t n = effects.size() / units;
  std::vector<std::size_t> rows(n);
  for (std::size_t t = 0; t < n; ++t) rows[t] = t;
  Measures point = measures(effects, units, rows);
  MorrisIndices out;
  out.mu = point.mu, out.mu_star = point.mu_star, out.sigma = point.sigma;
  out.effects = point.count;
  out.trajectories = n;
  for (auto* ci : {&out.mu_ci, &out.mu_star_ci, &out.sigma_ci}) ci->assign(2 * units, kNaN);
  if (resamples <= 0 || n < 2) {
    out.ranking = analysis::rank_units(out.mu_star, {}, n);
    return out;
  }
  // Resample r draws trajectory j as floor(u T), u from (seed, r, j).
  const auto count = static_cast<std::size_t>(resamples);
  std::vector<double> mu(count * units), mu_star(count * units), sigma(count * units);  // resample-major
  for (std::size_t r = 0; r < count; ++r) {
    for (std::size_t j = 0; j < n; ++j) {
      const double u = sampling::counter_uniform(seed, r, j, kTrajectoryBootstrapStream);
      rows[j] = std::min(static_cast<std::size_t>(u * static_cast<double>(n)), n - 1);
    }
    const Measures m = measures(effects, units, rows);
    const auto at = static_cast<std::ptrdiff_t>(r * units);
    std::copy(m.mu.begin(), m.mu.end(), mu.begin() + at);
    std::copy(m.mu_star.begin(), m.mu_star.end(), mu_star.begin() + at);
    std::copy(m.sigma.begin(), m.sigma.end(), sigma.begin() + at);
  }
  analysis::percentile_intervals(mu, units, out.mu_ci);
  analysis::percentile_intervals(mu_star, units, out.mu_star_ci);
  analysis::percentile_intervals(sigma, units, out.sigma_ci);
  out.ranking = analysis::rank_units(out.mu_star, mu_star, n);
  return out;
}

namespace {

// Radial steps: run s of trajectory t is A_t with unit s - 1's inputs from
// B_t, so its effect is (f_s - f_0) / step, the step b - a of a single
// input (signed) or, for a group, the root mean square of its inputs'.
std::vector<double> radial_effects(const EnsembleSpec& spec, const ensemble::ResponseTable& table, std::size_t r) {
  const unsigned units = spec.unit_count(), dimensions = spec.input_dimensions();
  const std::vector<unsigned> unit_of = spec.unit_of_input();
  const SampleDesign design(sampling::Design::morris, spec.seed, spec.runs, dimensions, unit_of, spec.morris);
  const std::uint64_t per = units + 1u, trajectories = table.samples() / per;
  std::vector<double> effects(trajectories * units, kNaN), a(dimensions), b(dimensions);
  auto value = [&](std::uint64_t k) { return table.ok(k) ? table.response(k, r) : kNaN; };
  for (std::uint64_t t = 0; t < trajectories; ++t) {
    design.point(t * per, a);
    const double before = value(t * per);
    for (unsigned g = 0; g < units; ++g) {
      design.point(t * per + g + 1, b);
      double step = 0.0, inputs = 0.0, last = 0.0;
      for (unsigned i = 0; i < dimensions; ++i)
        if (unit_of[i] == g) step += (b[i] - a[i]) * (b[i] - a[i]), inputs += 1.0, last = b[i] - a[i];
      step = inputs == 1.0 ? last : std::sqrt(step / inputs);
      const double after = value(t * per + g + 1);
      if (std::isfinite(before) && std::isfinite(after) && step != 0.0)
        effects[t * units + g] = (after - before) / step;
    }
  }
  return effects;
}

}  // namespace

std::vector<double> elementary_effects(const EnsembleSpec& spec, const ensemble::ResponseTable& table, std::size_t r) {
  if (spec.morris->radial) return radial_effects(spec, table, r);
  const unsigned units = spec.unit_count();
  const MorrisPoints points(spec.seed, spec.morris->levels, spec.unit_of_input(), units);
  const std::uint64_t per = points.runs_per_trajectory(), trajectories = table.samples() / per;
  std::vector<double> effects(trajectories * units, kNaN);
  auto value = [&](std::uint64_t k) { return table.ok(k) ? table.response(k, r) : kNaN; };
  for (std::uint64_t t = 0; t < trajectories; ++t) {
    const std::vector<MorrisStep> steps = points.steps(t);
    for (std::uint64_t s = 1; s < per; ++s) {
      const double before = value(t * per + s - 1), after = value(t * per + s);
      if (!std::isfinite(before) || !std::isfinite(after)) continue;
      const MorrisStep& step = steps[s - 1];
      effects[t * units + step.unit] = step.direction * (after - before) / kMorrisDelta;
    }
  }
  return effects;
}

std::shared_ptr<const MorrisAnswer> answer_morris(const EnsembleSpec& spec, const ensemble::ResponseTable& table,
                                                  std::size_t r) {
  auto a = std::make_shared<MorrisAnswer>();
  a->indices =
      morris_indices(elementary_effects(spec, table, r), spec.unit_count(), spec.bootstrap_resamples, spec.seed);
  return a;
}

}  // namespace treedyn::designs
