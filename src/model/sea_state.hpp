// A random sea state as base motion: per axis, a one-sided wave spectrum
// S(f) realised as a sum of harmonics with given phases,
//   eta(t) = sum_k a_k sin(2 pi f_k t + phi_k),   a_k = sqrt(2 S(f_k) df),
// on `components` equal bins of [min_frequency, max_frequency] (f_k at the
// bin centres), optionally through a response-amplitude operator (RAO) that
// turns wave elevation into the base point's motion:
//   r0_axis(t) = offset + sum_k G(f_k) a_k sin(2 pi f_k t + phi_k + theta(f_k)).
// The frequency grid is fixed by the job's nominal values (so a sample that
// changes Hs or Tp changes amplitudes, not frequencies); the harmonic sum is
// exact, so position, velocity and acceleration are analytic.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "common/linalg.hpp"

namespace treedyn {

enum class WaveSpectrum { jonswap, pierson_moskowitz, tabulated };

// Response-amplitude operator: gain G (m of base motion per m of wave) and
// phase theta (rad), linear in frequency between the table's rows.
struct ResponseAmplitudeOperator {
  std::vector<double> frequencies;  // Hz, strictly increasing
  std::vector<double> gains;        // 1 (m/m)
  std::vector<double> phases;       // rad
  bool empty() const { return frequencies.empty(); }
};

struct SeaStateAxis {
  WaveSpectrum spectrum = WaveSpectrum::jonswap;
  double significant_height = 0.0;                         // Hs, m (jonswap, pierson_moskowitz)
  double peak_period = 0.0;                                // Tp, s (jonswap, pierson_moskowitz)
  double gamma = 3.3;                                      // peak enhancement, 1 (jonswap; pierson_moskowitz is 1)
  std::vector<double> table_frequencies, table_densities;  // tabulated: Hz, m^2/Hz (one-sided)
  double min_frequency = 0.0, max_frequency = 0.0;         // Hz, the band of the components
  std::vector<double> phases;                              // phi_k, rad; one per component
  ResponseAmplitudeOperator rao;
  // -1: this axis has waves of its own. 0, 1, 2: it moves with the waves of
  // that axis (the same spectrum, Hs, Tp and phases, so the two motions are
  // coherent) through its own RAO; the reader and derive_model copy them.
  int wave_of = -1;
  int components() const { return static_cast<int>(phases.size()); }
};

// Copies the wave (spectrum, its parameters, band and phases) of the axis
// each follower follows into the follower, keeping the follower's RAO.
void share_waves(std::array<std::optional<SeaStateAxis>, 3>& axes);

struct SeaStateBase {
  Vec3 offset = Vec3::Zero();                       // m, mean position of the base point
  std::array<std::optional<SeaStateAxis>, 3> axes;  // x, y, z; an absent axis does not move
};

// S(f), m^2/Hz. JONSWAP (DNV-RP-C205 3.5.5) with sigma = 0.07 below the peak
// and 0.09 above, scaled so that its integral over (0, inf) is exactly
// Hs^2 / 16 (DNV's 1 - 0.287 ln gamma approximates that factor, within 2 %
// for gamma up to 7);
// Pierson-Moskowitz is gamma = 1; a table is interpolated linearly and is
// zero outside its frequencies.
double spectral_density(const SeaStateAxis& axis, double f);

// Default band for a parametric spectrum of peak period tp: [0.5, 3.5] / tp
// (a Pierson-Moskowitz spectrum keeps 99.2 % of its m0 there); a table's
// band is its own frequency range (a band must lie inside it).
std::array<double, 2> default_band(const SeaStateAxis& axis);

// What `treedyn check` prints about one axis, and what the tests compare to.
struct SeaStateSummary {
  double m0_components = 0.0;  // sum a_k^2 / 2: the variance of the realised elevation, m^2
                               // (a midpoint rule of m0 over the band: it may exceed the
                               // spectrum's own m0 when few components resolve a sharp peak)
  double m0_spectrum = 0.0;    // integral of S over (0, inf) (Hs^2/16 for a parametric one), m^2
  double base_variance = 0.0;  // sum (G a_k)^2 / 2: the variance of the base motion, m^2
  double df = 0.0;             // bin width, Hz; the sum repeats every 1/df s
};
SeaStateSummary summarize(const SeaStateAxis& axis);

// Checks one axis (finite, positive Hs and Tp, 1 <= gamma <= 20, a band
// inside a table's and an RAO's frequencies, some energy in the band, ...);
// throws ModelError saying which axis and what is allowed.
void validate_sea_state(const SeaStateAxis& axis, const std::string& axis_name);

// Amplitude, frequency and phase of component k: what the base moves by.
struct SeaComponent {
  double amplitude, frequency, phase;  // m, Hz, rad
};
std::vector<SeaComponent> components(const SeaStateAxis& axis);

}  // namespace treedyn
