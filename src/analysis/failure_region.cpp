#include "analysis/failure_region.hpp"

#include <boost/math/distributions/normal.hpp>
#include <boost/math/special_functions/digamma.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace treedyn::analysis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Every input column's perturbation (an orientation's three, a list's
// entries share theirs).
std::vector<const sampling::Perturbation*> owners(const EnsembleSpec& spec) {
  std::vector<const sampling::Perturbation*> out;
  for (const sampling::Perturbation& p : spec.perturbations)
    for (int k = 0; k < p.dimensions(); ++k) out.push_back(&p);
  return out;
}

// Whether the distribution has a bound where it is cut off: a truncated
// normal or a uniform, but not a uniform over a whole turn of an angle
// (periodic: its ends are one point).
bool bounded(const sampling::Perturbation& p) {
  const sampling::Distribution& d = p.distribution;
  if (d.kind != sampling::Distribution::Kind::truncated_normal && d.kind != sampling::Distribution::Kind::uniform)
    return false;
  const bool full_turn = p.si_unit == "rad" && p.mode != sampling::Perturbation::Mode::scale &&
                         (d.upper - d.lower) * p.unit >= 2.0 * std::numbers::pi * (1.0 - 1e-12);
  return !full_turn;
}

// u = Phi^-1(F(x)) of every input of row k, then through the copula's
// inverse: F rounds to 0 or 1 at a bound, so it is kept within 2^-53 of
// them (|u| <= 8.2, where the design's own uniforms end).
std::vector<double> normal_point(const EnsembleSpec& spec, const std::vector<const sampling::Perturbation*>& owner,
                                 const sampling::NormalCopula& copula, const ensemble::ResponseTable& table,
                                 std::uint64_t k) {
  const boost::math::normal standard;
  std::vector<double> u(owner.size());
  for (std::size_t i = 0; i < owner.size(); ++i) {
    const double f = owner[i]->distribution.cdf(table.input(k, i) / owner[i]->unit);
    u[i] = boost::math::quantile(standard, std::clamp(f, 0x1p-53, 1.0 - 0x1p-53));
  }
  if (!spec.correlations.empty()) copula.decorrelate(u);
  return u;
}

// The inputs (SI) at the normal point u: the design's own mapping.
std::vector<double> inputs_at(const std::vector<const sampling::Perturbation*>& owner,
                              const sampling::NormalCopula& copula, const std::vector<double>& u) {
  const boost::math::normal standard;
  std::vector<double> uniform(u.size()), x(u.size());
  for (std::size_t i = 0; i < u.size(); ++i)
    uniform[i] = std::clamp(boost::math::cdf(standard, u[i]), 0x1p-53, 1.0 - 0x1p-53);
  if (!copula.empty()) copula.correlate(uniform);
  for (std::size_t i = 0; i < u.size(); ++i) x[i] = owner[i]->distribution.quantile(uniform[i]) * owner[i]->unit;
  return x;
}

// The share of the failing rows near a bound of input i, and that bound.
void near_bound(const sampling::Perturbation& p, const ensemble::ResponseTable& table,
                const std::vector<std::uint64_t>& rows, std::size_t i, double& share, double& bound) {
  share = bound = kNaN;
  if (!bounded(p)) return;
  const sampling::Distribution& d = p.distribution;
  const double band = kNearBoundShare * (d.upper - d.lower);
  std::uint64_t low = 0, high = 0;
  for (const std::uint64_t k : rows) {
    const double x = table.input(k, i) / p.unit;
    low += x - d.lower <= band;
    high += d.upper - x <= band;
  }
  share = static_cast<double>(low + high) / static_cast<double>(rows.size());
  bound = (high >= low ? d.upper : d.lower) * p.unit;
}

// What the estimate of the divergence below averages to for an input the
// failure does not select on (u ~ N(0, 1) in the failing runs too), over n
// independent runs: with m of variance 1 / n and s^2 ~ chi^2_{n-1} / (n - 1),
// E[(s^2 + m^2 - 1 - ln s^2) / 2] = (1 / n + ln((n - 1) / 2) - psi((n - 1) / 2)) / 2.
// Taking it off each input leaves what the failing runs show beyond chance
// (with many inputs and few runs, chance alone would otherwise add up).
double null_divergence(double n) {
  if (n < 2.0) return 0.5;  // one run: its shift alone, m^2 / 2 with m ~ N(0, 1)
  return 0.5 * (1.0 / n + std::log((n - 1.0) / 2.0) - boost::math::digamma((n - 1.0) / 2.0));
}

// Per unit, max(sum of its inputs' divergences - their count x chance, 0),
// as shares of their sum (NaN when none departs beyond chance).
std::vector<double> shares_beyond_chance(const FailureRegion& region, const std::vector<InputUnit>& units) {
  std::vector<double> beyond(units.size());
  double total = 0.0;
  for (std::size_t u = 0; u < units.size(); ++u) {
    double sum = 0.0;
    for (const unsigned i : units[u].inputs) sum += region.divergence[i];
    beyond[u] = std::max(sum - static_cast<double>(units[u].inputs.size()) * region.chance, 0.0);
    total += beyond[u];
  }
  for (double& v : beyond) v = total > 0.0 ? v / total : kNaN;
  return beyond;
}

}  // namespace

FailureRegion failure_region(const EnsembleSpec& spec, const ensemble::ResponseTable& table, std::size_t r,
                             const std::function<bool(std::uint64_t)>& counted, double correlation) {
  FailureRegion region;
  const Response& response = spec.responses[r];
  std::vector<std::uint64_t> rows;
  for (std::uint64_t k = 0; k < table.samples(); ++k)
    if (counted(k) && table.ok(k) && response.exceeds(table.response(k, r))) rows.push_back(k);
  region.runs = rows.size();
  const std::size_t d = table.input_count();
  if (rows.empty() || d == 0) return region;

  const std::vector<const sampling::Perturbation*> owner = owners(spec);
  const sampling::NormalCopula copula = spec.correlations.empty()
                                            ? sampling::NormalCopula()
                                            : sampling::NormalCopula(static_cast<unsigned>(d), spec.correlations);
  std::vector<double> sum(d, 0.0), squares(d, 0.0);
  for (const std::uint64_t k : rows) {
    const std::vector<double> u = normal_point(spec, owner, copula, table, k);
    for (std::size_t i = 0; i < d; ++i) sum[i] += u[i], squares[i] += u[i] * u[i];
  }
  const double n = static_cast<double>(rows.size());
  region.effective_runs = n / (1.0 + std::max(correlation, 0.0));
  region.chance = null_divergence(region.effective_runs);
  region.divergence.resize(d);
  region.mean_u.resize(d), region.mean_u2.resize(d), region.near_bound.resize(d), region.bound.resize(d);
  for (std::size_t i = 0; i < d; ++i) {
    const double m = sum[i] / n, m2 = squares[i] / n;
    region.mean_u[i] = m;
    region.mean_u2[i] = m2;
    // The spread with n - 1 (unbiased: an input the failure does not select on
    // then has KL of order 1 / n); one run (or identical ones) has none, and its
    // divergence is its shift alone.
    const double s2 = rows.size() > 1 ? std::max(m2 - m * m, 0.0) * n / (n - 1.0) : 0.0;
    region.divergence[i] = s2 > 0.0 ? 0.5 * (s2 + m * m - 1.0 - std::log(s2)) : 0.5 * m * m;
    near_bound(*owner[i], table, rows, i, region.near_bound[i], region.bound[i]);
  }
  std::vector<InputUnit> alone;
  for (unsigned i = 0; i < d; ++i) alone.push_back({"", {i}});
  region.importance = shares_beyond_chance(region, alone);
  region.units = input_units(spec);
  region.unit_importance = shares_beyond_chance(region, region.units);
  region.design_point = inputs_at(owner, copula, region.mean_u);
  return region;
}

std::vector<InputUnit> input_units(const EnsembleSpec& spec) {
  std::vector<InputUnit> units;
  if (spec.grouped) {
    for (const SobolUnit& u : spec.sobol_units) units.push_back({u.name, u.inputs});
    return units;
  }
  const std::vector<std::string> names = spec.input_names();
  unsigned d = 0;
  for (const sampling::Perturbation& p : spec.perturbations) {
    const auto n = static_cast<unsigned>(p.dimensions());
    if (p.kind == sampling::Perturbation::Kind::parameter_list) {
      units.push_back({p.target, {}});
      for (unsigned k = 0; k < n; ++k) units.back().inputs.push_back(d + k);
    } else {
      for (unsigned k = 0; k < n; ++k) units.push_back({names[d + k], {d + k}});
    }
    d += n;
  }
  return units;
}

}  // namespace treedyn::analysis
