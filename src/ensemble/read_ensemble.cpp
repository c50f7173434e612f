#include <cmath>
#include <numbers>

#include "ensemble/ensemble_spec.hpp"
#include "ensemble/targets.hpp"
#include "job/toml_view.hpp"
#include "output/quantities.hpp"

namespace treedyn::ensemble {
namespace {

using Kind = Perturbation::Kind;
using Mode = Perturbation::Mode;

// Unit of the sampled values: angles need "deg" or "rad"; angular velocity
// "rad/s" (default) or "deg/s"; everything else is in its SI unit. A scale
// factor is dimensionless: no unit.
double read_unit(const TomlView& t, const Perturbation& p) {
  const auto unit = t.string("unit");
  if (p.mode == Mode::scale) {
    if (unit) t.fail("unit", "mode = \"scale\" samples a dimensionless factor; remove 'unit'");
    return 1.0;
  }
  if (p.si_unit == "rad") {
    if (unit == "deg") return std::numbers::pi / 180.0;
    if (unit == "rad") return 1.0;
    t.fail("unit", "an angle needs unit = \"deg\" or \"rad\"");
  }
  if (p.si_unit == "rad/s") {
    if (!unit || *unit == "rad/s") return 1.0;
    if (*unit == "deg/s") return std::numbers::pi / 180.0;
    t.fail("unit", "angular velocity: unit must be \"rad/s\" or \"deg/s\"");
  }
  if (unit) t.fail("unit", "this target is in SI units (" + p.si_unit + "); remove 'unit'");
  return 1.0;
}

inline constexpr NameTable<Mode, 3> kModeNames{
    {{Mode::set, "set"}, {Mode::add, "add"}, {Mode::scale, "scale"}}};

Distribution read_distribution(const TomlView& t) {
  Distribution d;
  const std::string kind = t.required_string("distribution");
  if (!parse_distribution(kind, d.kind))
    t.fail("distribution", "\"" + kind +
                               "\" is not allowed; use " + choices(kDistributionNames));
  auto positive = [&](std::string_view key) {
    const double v = t.required_number(key);
    if (!(v > 0.0)) t.fail(key, "must be > 0");
    return v;
  };
  switch (d.kind) {
    case Distribution::Kind::normal:
      d.mean = t.number("mean", 0.0);
      d.std = positive("std");
      break;
    case Distribution::Kind::truncated_normal: {
      d.mean = t.number("mean", 0.0);
      d.std = positive("std");
      d.lower = t.required_number("lower");
      d.upper = t.required_number("upper");
      if (!(d.lower < d.upper)) t.fail("upper", "must be greater than 'lower'");
      Distribution untruncated = d;
      untruncated.kind = Distribution::Kind::normal;
      if (!(untruncated.cdf(d.upper) - untruncated.cdf(d.lower) > 1e-12))
        t.fail("lower", "the interval [lower, upper] holds no probability of the normal");
      break;
    }
    case Distribution::Kind::uniform:
      d.lower = t.required_number("lower");
      d.upper = t.required_number("upper");
      if (!(d.lower < d.upper)) t.fail("upper", "must be greater than 'lower'");
      break;
    case Distribution::Kind::lognormal:
      d.mu = t.number("mu", 0.0);
      d.sigma = positive("sigma");
      break;
  }
  return d;
}

}  // namespace

double statistics_bytes(const Job& job, const EnsembleSpec& spec) {
  const std::size_t columns = column_layout(job.model, job.output).columns;
  const double entries =
      static_cast<double>(job.request.output_times.size()) * static_cast<double>(columns);
  // uint32 bin counters (bins + under/overflow), two 128-bit sums, min, max,
  // an out-of-range count, the calibration (4 doubles), the nominal and pilot
  // range (3 doubles), one sample's trajectory and, at worst (one rank), every
  // pilot trajectory.
  return entries * (4.0 * (spec.histogram_bins + 2) + 2 * 16.0 + 3 * 8.0 + 4 * 8.0 + 3 * 8.0 +
                    8.0 * (1.0 + static_cast<double>(spec.pilot_samples)));
}

void print_ensemble_summary(std::ostream& out, const Job& job, const EnsembleSpec& s) {
  out << "ensemble: " << s.samples << " samples, seed " << s.seed << ", design " << name(s.design)
      << ", " << s.perturbations.size() << " perturbation" << (s.perturbations.size() == 1 ? "" : "s")
      << " (" << s.input_dimensions() << " sampled inputs)\n";
  const auto nominal = job.definition.parameters.nominal();
  for (const Perturbation& p : s.perturbations) {
    out << "  " << p.target << ": " << p.distribution.describe();
    if (p.unit != 1.0) out << " x " << format_number(p.unit) << " (to " << p.si_unit << ")";
    if (p.kind == Kind::orientation)
      out << " per rotation-vector component, rad";
    else if (p.kind == Kind::rotation)
      out << ", rad, composed with the nominal orientation";
    else if (p.entries > 1)
      out << (p.mode == Mode::scale ? " multiplies the matrix"
              : p.mode == Mode::add ? " x E is added to the matrix"
                                    : " x E replaces the matrix");
    else
      out << (p.mode == Mode::scale ? " multiplies" : p.mode == Mode::add ? " is added to" : " replaces")
          << " the nominal "
          << (p.kind == Kind::parameter ? nominal[p.first] / p.factor
                                        : job.initial.angular_velocity[p.first][p.axis])
          << " " << p.si_unit;
    out << "\n      " << p.enters << "\n";
  }
  out << "statistics: quantiles";
  for (double q : s.quantiles) out << " " << format_number(q);
  out << "; " << s.histogram_bins << " histogram bins; pilot samples 0-" << s.pilot_samples - 1
      << "; blocks of " << s.block_size << "; about "
      << format_number(std::round(statistics_bytes(job, s) / (1024.0 * 1024.0))) << " MiB per rank\n";
}

unsigned EnsembleSpec::input_dimensions() const {
  unsigned d = 0;
  for (const Perturbation& p : perturbations) d += static_cast<unsigned>(p.dimensions());
  return d;
}

std::vector<std::string> EnsembleSpec::input_names() const {
  std::vector<std::string> names;
  for (const Perturbation& p : perturbations)
    for (auto& n : p.input_names()) names.push_back(n);
  return names;
}

EnsembleSpec read_ensemble(const Job& job) {
  toml::table root_table;
  try {
    root_table = toml::parse(job.text, job.file);
  } catch (const toml::parse_error& e) {
    throw JobError(job.file, static_cast<int>(e.source().begin.line),
                   static_cast<int>(e.source().begin.column), "", e.description().data());
  }
  const TomlView root(root_table, "", job.file);
  const auto section = root.subtable("ensemble");
  if (!section)
    throw JobError(job.file, 0, 0, "ensemble",
                   "missing [ensemble] section: give at least samples = N (and seed, perturbations)");
  const TomlView& t = *section;
  t.check_keys({"samples", "seed", "design", "quantiles", "histogram_bins", "pilot_samples",
                "block_size", "perturbation"});
  EnsembleSpec s;
  const auto samples = t.integer("samples");
  if (!samples) t.fail("samples", "missing required field: the number of samples (integer >= 1)");
  if (*samples < 1) t.fail("samples", "must be at least 1");
  s.samples = static_cast<std::uint64_t>(*samples);
  if (auto seed = t.integer("seed")) {
    if (*seed < 0) t.fail("seed", "must be a non-negative integer");
    s.seed = static_cast<std::uint64_t>(*seed);
  }
  if (auto design = t.string("design"); design && !parse_design(*design, s.design))
    t.fail("design", "\"" + *design +
                         "\" is not allowed; use " + choices(kDesignNames));
  if (auto q = t.numbers("quantiles")) {
    for (double v : *q)
      if (!(v > 0.0 && v < 1.0)) t.fail("quantiles", "every quantile must be in (0, 1)");
    s.quantiles = *q;
  }
  if (auto bins = t.integer("histogram_bins")) {
    if (*bins < 2 || *bins > 100000) t.fail("histogram_bins", "must be from 2 to 100000");
    s.histogram_bins = static_cast<int>(*bins);
  }
  if (auto pilot = t.integer("pilot_samples")) {
    if (*pilot < 1) t.fail("pilot_samples", "must be at least 1");
    s.pilot_samples = static_cast<std::uint64_t>(*pilot);
  }
  s.pilot_samples = std::min(s.pilot_samples, s.samples);
  if (auto block = t.integer("block_size")) {
    if (*block < 1) t.fail("block_size", "must be at least 1");
    s.block_size = static_cast<std::uint64_t>(*block);
  }
  for (const TomlView& p : t.table_array("perturbation")) {
    p.check_keys({"target", "distribution", "mean", "std", "lower", "upper", "mu", "sigma",
                  "mode", "unit"});
    Perturbation pert;
    pert.target = p.required_string("target");
    try {
      const Target target = resolve_target(job.definition, pert.target);
      pert.kind = target.kind;
      pert.first = target.first;
      pert.entries = target.entries;
      pert.factor = target.factor;
      pert.axis = target.axis;
      pert.si_unit = target.unit;
      pert.enters = target.enters;
    } catch (const TargetError& e) {
      p.fail("target", e.what());
    }
    const std::string mode = p.string("mode").value_or("set");
    if (!parse_in(kModeNames, mode, pert.mode))
      p.fail("mode", "\"" + mode + "\" is not allowed; use " + choices(kModeNames));
    if ((pert.kind == Kind::orientation || pert.kind == Kind::rotation) && p.has("mode"))
      p.fail("mode", "not used for this target (a rotation is always composed with the nominal orientation)");
    pert.unit = read_unit(p, pert);
    pert.distribution = read_distribution(p);
    s.perturbations.push_back(pert);
  }
  if (s.design == Design::sobol && s.input_dimensions() > 1000)
    t.fail("perturbation", "sobol supports at most 1000 input dimensions");
  // 32-bit Sobol points and 32-bit histogram counters.
  if (s.samples > 0xffffffffULL) t.fail("samples", "at most 4294967295 samples");
  const double gib = statistics_bytes(job, s) / (1024.0 * 1024.0 * 1024.0);
  if (gib > 8.0)
    t.fail("histogram_bins", "the statistics would need " + format_number(std::round(gib)) +
                                 " GiB per rank (output times x columns x bins); at most 8: use "
                                 "fewer bins, output times or quantities");
  return s;
}

}  // namespace treedyn::ensemble
