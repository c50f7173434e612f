#include <charconv>
#include <cmath>
#include <numbers>

#include "ensemble/ensemble_spec.hpp"
#include "job/toml_view.hpp"
#include "output/quantities.hpp"

namespace treedyn::ensemble {
namespace {

using Field = Perturbation::Field;

int parse_axis(const TomlView& t, std::string_view text) {
  if (text == "x") return 0;
  if (text == "y") return 1;
  if (text == "z") return 2;
  t.fail("target", "axis '" + std::string(text) + "' is not allowed; use x, y or z");
}

std::vector<std::string> split(std::string_view s) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (std::size_t i = 0; i <= s.size(); ++i)
    if (i == s.size() || s[i] == '.') {
      parts.emplace_back(s.substr(start, i - start));
      start = i + 1;
    }
  return parts;
}

const char* kTargets =
    "allowed targets: body.NAME.mass, body.NAME.inertia_scale, "
    "body.NAME.joint_on_child.AXIS, body.NAME.joint_on_parent.AXIS, body.NAME.orientation, "
    "body.NAME.rotation.AXIS, body.NAME.angular_velocity.AXIS, joint.CHILD.stiffness, "
    "joint.CHILD.damping, base.AXIS[K].amplitude, base.AXIS[K].frequency, base.AXIS[K].phase, "
    "base.acceleration.AXIS, gravity.AXIS (AXIS = x, y or z; K counts from 1)";

void parse_target(const TomlView& t, const Job& job, Perturbation& p) {
  const ModelSpec& spec = job.model.spec;
  const std::vector<std::string> parts = split(p.target);
  auto bad = [&]() { t.fail("target", "'" + p.target + "' is not a target; " + kTargets); };
  if (parts.size() < 2) bad();
  if (parts[0] == "body" || parts[0] == "joint") {
    if (parts.size() < 3) bad();
    p.body = parts[1];
    for (std::size_t b = 0; b < spec.bodies.size(); ++b)
      if (spec.bodies[b].name == p.body) p.body_index = static_cast<int>(b);
    if (p.body_index < 0) t.fail("target", "'" + p.body + "' is not a body of the model");
    for (std::size_t j = 0; j < spec.joints.size(); ++j)
      if (spec.joints[j].child == p.body) p.joint_index = static_cast<int>(j);
    const std::string& what = parts[2];
    const bool has_axis = parts.size() == 4;
    if (parts.size() > 4) bad();
    if (parts[0] == "joint") {
      if (what == "stiffness" && !has_axis) p.field = Field::stiffness;
      else if (what == "damping" && !has_axis) p.field = Field::damping;
      else bad();
      return;
    }
    if (what == "mass" && !has_axis) p.field = Field::mass;
    else if (what == "inertia_scale" && !has_axis) p.field = Field::inertia_scale;
    else if (what == "orientation" && !has_axis) p.field = Field::orientation;
    else if (what == "joint_on_child" && has_axis) p.field = Field::joint_on_child;
    else if (what == "joint_on_parent" && has_axis) p.field = Field::joint_on_parent;
    else if (what == "rotation" && has_axis) p.field = Field::rotation;
    else if (what == "angular_velocity" && has_axis) p.field = Field::angular_velocity;
    else bad();
    if (has_axis) p.axis = parse_axis(t, parts[3]);
    return;
  }
  if (parts[0] == "gravity" && parts.size() == 2) {
    p.field = Field::gravity;
    p.axis = parse_axis(t, parts[1]);
    return;
  }
  if (parts[0] == "base" && parts.size() == 3 && parts[1] == "acceleration") {
    if (!std::holds_alternative<ConstantAccelerationBase>(spec.base_motion))
      t.fail("target", "'" + p.target + "' needs [base] type = \"constant_acceleration\"");
    p.field = Field::base_acceleration;
    p.axis = parse_axis(t, parts[2]);
    return;
  }
  if (parts[0] == "base" && parts.size() == 3) {
    // base.AXIS[K].what
    const std::string& term = parts[1];
    const auto open = term.find('['), close = term.find(']');
    if (open != 1 || close != term.size() - 1) bad();
    p.axis = parse_axis(t, term.substr(0, 1));
    int k = 0;
    const auto [ptr, ec] = std::from_chars(term.data() + 2, term.data() + close, k);
    if (ec != std::errc() || ptr != term.data() + close || k < 1) bad();
    p.term = k - 1;
    const auto* h = std::get_if<HarmonicBase>(&spec.base_motion);
    if (!h) t.fail("target", "'" + p.target + "' needs [base] type = \"harmonic\"");
    if (p.term >= static_cast<int>(h->axes[p.axis].size()))
      t.fail("target", "'" + p.target + "': the base has " +
                           std::to_string(h->axes[p.axis].size()) + " terms on that axis");
    if (parts[2] == "amplitude") p.field = Field::base_amplitude;
    else if (parts[2] == "frequency") p.field = Field::base_frequency;
    else if (parts[2] == "phase") p.field = Field::base_phase;
    else bad();
    return;
  }
  bad();
}

// Unit of the sampled values: angles need "deg" or "rad"; angular velocity
// "rad/s" (default) or "deg/s"; everything else is SI. A scale factor is
// dimensionless: no unit.
double read_unit(const TomlView& t, Field field, Perturbation::Mode mode) {
  const auto unit = t.string("unit");
  if (mode == Perturbation::Mode::scale) {
    if (unit) t.fail("unit", "mode = \"scale\" samples a dimensionless factor; remove 'unit'");
    return 1.0;
  }
  const bool angle = field == Field::orientation || field == Field::rotation || field == Field::base_phase;
  if (angle) {
    if (unit == "deg") return std::numbers::pi / 180.0;
    if (unit == "rad") return 1.0;
    t.fail("unit", "an angle needs unit = \"deg\" or \"rad\"");
  }
  if (field == Field::angular_velocity) {
    if (!unit || *unit == "rad/s") return 1.0;
    if (*unit == "deg/s") return std::numbers::pi / 180.0;
    t.fail("unit", "angular velocity: unit must be \"rad/s\" or \"deg/s\"");
  }
  if (unit) t.fail("unit", "this target is in SI units; remove 'unit'");
  return 1.0;
}

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
  std::size_t columns = 0;
  for (const std::string& q : job.output.quantities)
    columns += quantity_columns(q, job.model, job.output).size();
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
  for (const Perturbation& p : s.perturbations) {
    out << "  " << p.target << ": " << p.distribution.describe();
    if (p.unit != 1.0) out << " x " << format_number(p.unit) << " (to SI)";
    if (p.field == Perturbation::Field::orientation) out << ", per rotation-vector component";
    else if (p.mode == Perturbation::Mode::add) out << ", added to the nominal value";
    else if (p.mode == Perturbation::Mode::scale || p.field == Perturbation::Field::inertia_scale)
      out << ", multiplies the nominal value";
    out << "\n";
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
    parse_target(p, job, pert);
    const std::string mode = p.string("mode").value_or("set");
    if (mode == "set") pert.mode = Perturbation::Mode::set;
    else if (mode == "add") pert.mode = Perturbation::Mode::add;
    else if (mode == "scale") pert.mode = Perturbation::Mode::scale;
    else p.fail("mode", "\"" + mode + "\" is not allowed; use \"set\", \"add\" or \"scale\"");
    if ((pert.field == Field::orientation || pert.field == Field::rotation ||
         pert.field == Field::inertia_scale) && p.has("mode"))
      p.fail("mode", "not used for this target (a rotation is always added, inertia_scale always scales)");
    pert.unit = read_unit(p, pert.field, pert.mode);
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
