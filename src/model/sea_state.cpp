#include "model/sea_state.hpp"

#include <algorithm>
#include <cmath>

#include "common/error.hpp"
#include "common/format.hpp"
#include "model/model_spec.hpp"

namespace treedyn {
namespace {

// The Pierson-Moskowitz shape in x = f / fp: x^-5 exp(-5/4 x^-4); its
// integral over (0, inf) is 1/5.
double pm_shape(double x) { return std::pow(x, -5.0) * std::exp(-1.25 * std::pow(x, -4.0)); }

// JONSWAP's peak enhancement gamma^r(x).
double peak_factor(double gamma, double x) {
  const double sigma = x <= 1.0 ? 0.07 : 0.09;
  const double r = std::exp(-0.5 * std::pow((x - 1.0) / (sigma), 2.0));
  return std::pow(gamma, r);
}

// Integral of pm_shape(x) gamma^r(x) over (0, inf): 1/5 plus the peak's
// extra, which lives within 0.07 * 9 below and 0.09 * 11 above x = 1 (there
// gamma^r - 1 < 1e-17 gamma); composite Simpson on 4000 intervals of [0.3, 2.1].
double jonswap_integral(double gamma) {
  if (gamma == 1.0) return 0.2;
  constexpr int n = 4000;
  constexpr double a = 0.3, b = 2.1, h = (b - a) / n;
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double x = a + i * h;
    const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    sum += w * pm_shape(x) * (peak_factor(gamma, x) - 1.0);
  }
  return 0.2 + sum * h / 3.0;
}

// Linear interpolation in a table; `outside` beyond its ends.
double interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double x, double outside) {
  if (xs.empty() || x < xs.front() || x > xs.back()) return outside;
  const auto hi = std::upper_bound(xs.begin(), xs.end(), x);
  if (hi == xs.end()) return ys.back();
  const auto i = static_cast<std::size_t>(hi - xs.begin());
  const double t = (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
  return ys[i - 1] + t * (ys[i] - ys[i - 1]);
}

double table_integral(const SeaStateAxis& a) {
  double m0 = 0.0;
  for (std::size_t i = 1; i < a.table_frequencies.size(); ++i)
    m0 +=
        0.5 * (a.table_densities[i] + a.table_densities[i - 1]) * (a.table_frequencies[i] - a.table_frequencies[i - 1]);
  return m0;
}

double effective_gamma(const SeaStateAxis& a) { return a.spectrum == WaveSpectrum::jonswap ? a.gamma : 1.0; }

// The integral of the spectrum's shape, computed once per axis (not per component).
// The last gamma's integral is kept: spectral_density() point by point (a
// plot, a check) then costs a few exp, not a quadrature.
double normalisation(const SeaStateAxis& a) {
  if (a.spectrum == WaveSpectrum::tabulated) return 1.0;
  thread_local double last_gamma = 1.0, last_integral = 0.2;
  const double gamma = effective_gamma(a);
  if (gamma != last_gamma) {
    last_integral = jonswap_integral(gamma);
    last_gamma = gamma;
  }
  return last_integral;
}

// S(f) given the shape's integral `norm`.
double density(const SeaStateAxis& a, double f, double norm) {
  if (a.spectrum == WaveSpectrum::tabulated) return interpolate(a.table_frequencies, a.table_densities, f, 0.0);
  if (!(f > 0.0)) return 0.0;
  const double x = f * a.peak_period;  // f / fp
  const double m0 = a.significant_height * a.significant_height / 16.0;
  return m0 * a.peak_period * pm_shape(x) * peak_factor(effective_gamma(a), x) / norm;
}

double bin_width(const SeaStateAxis& a) { return (a.max_frequency - a.min_frequency) / std::max(1, a.components()); }

[[noreturn]] void refuse(const std::string& axis_name, const std::string& what) {
  throw ModelError("base motion 'sea_state', axis " + axis_name + ": " + what, kBaseName);
}

void require_table(const std::vector<double>& xs, const std::vector<double>& ys, const std::string& what,
                   const std::string& axis_name, bool non_negative) {
  if (xs.size() < 2 || xs.size() != ys.size())
    refuse(axis_name, what + ": need at least 2 rows and as many values as frequencies (got " +
                          std::to_string(xs.size()) + " and " + std::to_string(ys.size()) + ")");
  for (std::size_t i = 0; i < xs.size(); ++i) {
    if (!std::isfinite(xs[i]) || !std::isfinite(ys[i]) || xs[i] < 0.0 || (non_negative && ys[i] < 0.0))
      refuse(axis_name, what + ": row " + std::to_string(i + 1) + " must be finite, with frequency >= 0" +
                            (non_negative ? " and value >= 0" : ""));
    if (i > 0 && !(xs[i] > xs[i - 1]))
      refuse(axis_name, what + ": frequencies must be strictly increasing (row " + std::to_string(i + 1) + ")");
  }
}

// The band: ordered, inside a table's frequencies, and holding some energy.
void validate_band(const SeaStateAxis& a, const std::string& axis_name) {
  const std::string band = "[" + format_number(a.min_frequency) + ", " + format_number(a.max_frequency) + "] Hz";
  if (!(std::isfinite(a.min_frequency) && std::isfinite(a.max_frequency) && a.min_frequency >= 0.0 &&
        a.max_frequency > a.min_frequency))
    refuse(axis_name, "the band " + band + " is not allowed; need 0 <= min_frequency < max_frequency");
  if (a.spectrum == WaveSpectrum::tabulated &&
      (a.min_frequency < a.table_frequencies.front() || a.max_frequency > a.table_frequencies.back()))
    refuse(axis_name, "the band " + band + " reaches outside the tabulated spectrum's frequencies [" +
                          format_number(a.table_frequencies.front()) + ", " +
                          format_number(a.table_frequencies.back()) + "] Hz");
  SeaStateAxis no_rao = a;
  no_rao.rao = {};
  double m0 = 0.0;
  for (const SeaComponent& c : components(no_rao)) m0 += c.amplitude * c.amplitude;
  if (!(m0 > 0.0))
    refuse(axis_name, "the spectrum has no energy at the components' frequencies in the band " + band +
                          "; give a band where its density is positive");
}

void validate_parametric(const SeaStateAxis& a, const std::string& axis_name) {
  if (!(std::isfinite(a.significant_height) && a.significant_height > 0.0))
    refuse(axis_name, "significant_height = " + format_number(a.significant_height) + " m; it must be finite and > 0");
  if (!(std::isfinite(a.peak_period) && a.peak_period > 0.0))
    refuse(axis_name, "peak_period = " + format_number(a.peak_period) + " s; it must be finite and > 0");
  if (!(std::isfinite(a.gamma) && a.gamma >= 1.0 && a.gamma <= 20.0))
    refuse(axis_name,
           "gamma = " + format_number(a.gamma) + "; the peak enhancement must be from 1 (Pierson-Moskowitz) to 20");
}

}  // namespace

double spectral_density(const SeaStateAxis& a, double f) { return density(a, f, normalisation(a)); }

std::array<double, 2> default_band(const SeaStateAxis& a) {
  if (a.spectrum == WaveSpectrum::tabulated)
    return {a.table_frequencies.empty() ? 0.0 : a.table_frequencies.front(),
            a.table_frequencies.empty() ? 0.0 : a.table_frequencies.back()};
  return {0.5 / a.peak_period, 3.5 / a.peak_period};
}

std::vector<SeaComponent> components(const SeaStateAxis& a) {
  std::vector<SeaComponent> out;
  out.reserve(a.phases.size());
  const double df = bin_width(a), norm = normalisation(a);
  for (int k = 0; k < a.components(); ++k) {
    const double f = a.min_frequency + (k + 0.5) * df;
    double amplitude = std::sqrt(2.0 * density(a, f, norm) * df), phase = a.phases[static_cast<std::size_t>(k)];
    if (!a.rao.empty()) {
      amplitude *= interpolate(a.rao.frequencies, a.rao.gains, f, 0.0);
      phase += interpolate(a.rao.frequencies, a.rao.phases, f, 0.0);
    }
    out.push_back({amplitude, f, phase});
  }
  return out;
}

void share_waves(std::array<std::optional<SeaStateAxis>, 3>& axes) {
  for (auto& follower : axes) {
    if (!follower || follower->wave_of < 0) continue;
    const SeaStateAxis& wave = *axes[static_cast<std::size_t>(follower->wave_of)];
    SeaStateAxis shared = wave;
    shared.rao = std::move(follower->rao);
    shared.wave_of = follower->wave_of;
    *follower = std::move(shared);
  }
}

SeaStateSummary summarize(const SeaStateAxis& a) {
  SeaStateSummary s;
  s.df = bin_width(a);
  SeaStateAxis no_rao = a;
  no_rao.rao = {};
  for (const SeaComponent& c : components(no_rao)) s.m0_components += 0.5 * c.amplitude * c.amplitude;
  for (const SeaComponent& c : components(a)) s.base_variance += 0.5 * c.amplitude * c.amplitude;
  s.m0_spectrum =
      a.spectrum == WaveSpectrum::tabulated ? table_integral(a) : a.significant_height * a.significant_height / 16.0;
  return s;
}

void validate_sea_state(const SeaStateAxis& a, const std::string& axis_name) {
  if (a.spectrum == WaveSpectrum::tabulated)
    require_table(a.table_frequencies, a.table_densities, "the tabulated spectrum", axis_name, true);
  else
    validate_parametric(a, axis_name);
  if (a.components() < 1 || a.components() > 10000)
    refuse(axis_name, "components = " + std::to_string(a.components()) + "; allowed: 1 to 10000");
  validate_band(a, axis_name);
  for (double phi : a.phases)
    if (!std::isfinite(phi)) refuse(axis_name, "every phase must be finite");
  if (!a.rao.empty()) {
    require_table(a.rao.frequencies, a.rao.gains, "rao", axis_name, true);
    for (double theta : a.rao.phases)
      if (!std::isfinite(theta)) refuse(axis_name, "rao: every phase must be finite");
    if (a.rao.phases.size() != a.rao.frequencies.size())
      refuse(axis_name, "rao: need one phase per frequency (got " + std::to_string(a.rao.phases.size()) + " and " +
                            std::to_string(a.rao.frequencies.size()) + ")");
    if (a.min_frequency < a.rao.frequencies.front() || a.max_frequency > a.rao.frequencies.back())
      refuse(axis_name, "rao: its frequencies [" + format_number(a.rao.frequencies.front()) + ", " +
                            format_number(a.rao.frequencies.back()) + "] Hz must cover the band of the components [" +
                            format_number(a.min_frequency) + ", " + format_number(a.max_frequency) +
                            "] Hz (set min_frequency and max_frequency, or extend the table)");
  }
}

}  // namespace treedyn
