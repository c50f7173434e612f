// [base] type = "sea_state": per-axis wave spectra (model/sea_state.hpp).
#include <cmath>
#include <numbers>
#include <string>

#include "common/error.hpp"
#include "job/readers.hpp"
#include "sampling/design.hpp"

namespace treedyn {
namespace {

constexpr int kDefaultComponents = 64;

double positive(const TomlView& t, std::string_view key, const std::string& unit) {
  const double v = t.required_number(key);
  if (!(std::isfinite(v) && v > 0.0)) t.fail(key, "must be a finite number > 0 " + unit);
  return v;
}

std::vector<double> required_numbers(const TomlView& t, std::string_view key, const std::string& what) {
  auto v = t.numbers(key);
  if (!v) t.fail(key, "missing required field: " + what);
  return *v;
}

// rao = { frequencies = [...] (Hz), gains = [...] (m/m), phases = [...], unit = "deg" | "rad" }
ResponseAmplitudeOperator read_rao(const TomlView& axis) {
  const auto table = axis.subtable("rao");
  if (!table) return {};
  const TomlView& r = *table;
  r.check_keys({"frequencies", "gains", "phases", "unit"});
  ResponseAmplitudeOperator rao;
  rao.frequencies = required_numbers(r, "frequencies", "the RAO's frequencies in Hz, increasing");
  rao.gains = required_numbers(r, "gains", "the RAO's gains (m of base motion per m of wave), one per frequency");
  if (r.has("unit") && !r.has("phases")) r.fail("unit", "the unit of the RAO's phases, but it has no phases");
  if (r.has("phases")) {
    const auto unit = r.string("unit");
    if (!unit || (*unit != "deg" && *unit != "rad")) r.fail("unit", "the RAO's phases need unit = \"deg\" or \"rad\"");
    rao.phases = required_numbers(r, "phases", "the RAO's phases, one per frequency");
    for (double& p : rao.phases) p *= *unit == "deg" ? std::numbers::pi / 180.0 : 1.0;
  } else {
    rao.phases.assign(rao.frequencies.size(), 0.0);
  }
  return rao;
}

void read_spectrum(const TomlView& t, SeaStateAxis& a) {
  const std::string spectrum = t.string("spectrum").value_or("jonswap");
  if (spectrum == "tabulated") {
    a.spectrum = WaveSpectrum::tabulated;
    for (const char* key : {"significant_height", "peak_period", "gamma"})
      if (t.has(key)) t.fail(key, "a tabulated spectrum is given by frequencies and densities; remove this field");
    a.table_frequencies = required_numbers(t, "frequencies", "the spectrum's frequencies in Hz, increasing");
    a.table_densities = required_numbers(t, "densities", "the one-sided spectral density in m^2/Hz, one per frequency");
    return;
  }
  if (spectrum != "jonswap" && spectrum != "pierson_moskowitz")
    t.fail("spectrum", "\"" + spectrum +
                           "\" is not a wave spectrum; allowed: \"jonswap\", \"pierson_moskowitz\", "
                           "\"tabulated\"");
  for (const char* key : {"frequencies", "densities"})
    if (t.has(key)) t.fail(key, "only a tabulated spectrum has this field (spectrum = \"tabulated\")");
  a.spectrum = spectrum == "jonswap" ? WaveSpectrum::jonswap : WaveSpectrum::pierson_moskowitz;
  a.significant_height = positive(t, "significant_height", "m");
  a.peak_period = positive(t, "peak_period", "s");
  if (a.spectrum == WaveSpectrum::pierson_moskowitz && t.has("gamma"))
    t.fail("gamma", "Pierson-Moskowitz has no peak enhancement (it is JONSWAP with gamma = 1); remove it");
  a.gamma = a.spectrum == WaveSpectrum::jonswap ? t.number("gamma", 3.3) : 1.0;
  if (!(a.gamma >= 1.0 && a.gamma <= 20.0))
    t.fail("gamma",
           "must be from 1 (Pierson-Moskowitz) to 20 (the peak enhancement of JONSWAP; 3.3 is the mean of "
           "the JONSWAP measurements)");
}

// Nominal phases phi_k, uniform on [0, 2 pi) from (phase_seed, axis, k): the
// same job gives the same sea on any machine.
std::vector<double> nominal_phases(std::uint64_t seed, int axis, int components) {
  std::vector<double> phases(static_cast<std::size_t>(components));
  for (int k = 0; k < components; ++k)
    phases[static_cast<std::size_t>(k)] =
        2.0 * std::numbers::pi *
        sampling::counter_uniform(seed, static_cast<std::uint64_t>(k), static_cast<std::uint64_t>(axis),
                                  0x736561);  // "sea"
  return phases;
}

// The field a validation message is about, for its position in the file.
std::string_view field_of(const std::string& what, const TomlView& t, const SeaStateAxis& a) {
  if (what.find("rao:") != std::string::npos) return "rao";
  if (what.find("no energy") != std::string::npos)
    return a.spectrum == WaveSpectrum::tabulated ? "densities" : "significant_height";
  if (what.find("tabulated spectrum:") != std::string::npos)
    return what.find("value >= 0") != std::string::npos && what.find("strictly") == std::string::npos ? "densities"
                                                                                                      : "frequencies";
  if (what.find("the band") != std::string::npos) {
    const bool low_wrong = !(a.min_frequency >= 0.0) ||
                           (a.spectrum == WaveSpectrum::tabulated && a.min_frequency < a.table_frequencies.front());
    std::string_view key = low_wrong ? "min_frequency" : "max_frequency";
    return t.has(key) ? key : (t.has("min_frequency") ? "min_frequency" : "max_frequency");
  }
  return "spectrum";
}

SeaStateAxis read_axis(const TomlView& t, int axis, std::uint64_t seed) {
  t.check_keys({"spectrum", "significant_height", "peak_period", "gamma", "frequencies", "densities", "components",
                "min_frequency", "max_frequency", "rao"});
  SeaStateAxis a;
  read_spectrum(t, a);
  const long components = t.integer("components").value_or(kDefaultComponents);
  if (components < 1 || components > 10000) t.fail("components", "must be from 1 to 10000");
  a.phases = nominal_phases(seed, axis, static_cast<int>(components));
  const auto band = default_band(a);
  a.min_frequency = t.number("min_frequency", band[0]);
  a.max_frequency = t.number("max_frequency", band[1]);
  a.rao = read_rao(t);
  try {
    validate_sea_state(a, std::string(1, "xyz"[axis]));
  } catch (const ModelError& e) {
    t.fail(field_of(e.what(), t, a), e.what());
  }
  return a;
}

// [base.AXIS] wave = "z": this axis moves with the waves of [base.z] (their
// spectrum, Hs, Tp and phases: one sea, coherent motions) through its own RAO.
int read_follower(const TomlView& t, const SeaStateBase& sea) {
  t.check_keys({"wave", "rao"});
  const std::string wave = t.required_string("wave");
  const int source = wave == "x" ? 0 : wave == "y" ? 1 : wave == "z" ? 2 : -1;
  if (source < 0 || !sea.axes[static_cast<std::size_t>(source)] ||
      sea.axes[static_cast<std::size_t>(source)]->wave_of >= 0)
    t.fail("wave", "\"" + wave +
                       "\" is not an axis with waves of its own; name one of this [base]'s axes whose table "
                       "gives a spectrum (\"x\", \"y\" or \"z\")");
  if (!t.subtable("rao"))
    t.fail("wave",
           "an axis that follows the waves of another needs its own [base.AXIS.rao] (without one it would "
           "move exactly as that axis)");
  return source;
}

}  // namespace

SeaStateBase read_sea_state(const TomlView& t) {
  t.check_keys({"type", "offset", "phase_seed", "x", "y", "z"});
  SeaStateBase sea;
  sea.offset = t.vec3("offset").value_or(Vec3::Zero());
  const long seed = t.integer("phase_seed").value_or(1);
  if (seed < 0) t.fail("phase_seed", "must be a non-negative integer");
  // Axes with waves of their own first, then those that follow one of them.
  for (bool followers : {false, true})
    for (int axis = 0; axis < 3; ++axis) {
      const auto table = t.subtable(std::string_view("xyz" + axis, 1));
      if (!table || table->has("wave") != followers) continue;
      if (!followers) {
        sea.axes[axis] = read_axis(*table, axis, static_cast<std::uint64_t>(seed));
        continue;
      }
      SeaStateAxis follower;
      follower.wave_of = read_follower(*table, sea);
      follower.rao = read_rao(*table);
      sea.axes[axis] = std::move(follower);
      share_waves(sea.axes);
      try {
        validate_sea_state(*sea.axes[axis], std::string(1, "xyz"[axis]));
      } catch (const ModelError& e) {
        table->fail("rao", e.what());
      }
    }
  if (!sea.axes[0] && !sea.axes[1] && !sea.axes[2])
    t.fail("type", "a sea state needs at least one axis table, [base.x], [base.y] or [base.z], with its spectrum");
  return sea;
}

}  // namespace treedyn
