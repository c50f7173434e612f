#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "designs/design_rules.hpp"
#include "job/ensemble_spec.hpp"
#include "job/readers.hpp"
#include "job/toml_document.hpp"
#include "job/toml_view.hpp"
#include "output/quantities.hpp"
#include "sampling/targets.hpp"
#include "statistics/ensemble_statistics.hpp"

namespace treedyn {
namespace {

constexpr std::uint64_t kMaxRuns = statistics::EnsembleStatistics::kMaxSamples;

using Kind = sampling::Perturbation::Kind;
using Mode = sampling::Perturbation::Mode;

// Unit of the sampled values: angles need "deg" or "rad"; angular velocity
// "rad/s" (default) or "deg/s"; everything else is in its SI unit. A scale
// factor is dimensionless: no unit.
double read_unit(const TomlView& t, const sampling::Perturbation& p) {
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

sampling::Distribution read_distribution(const TomlView& t) {
  sampling::Distribution d;
  const std::string kind = t.required_string("distribution");
  if (!sampling::parse_distribution(kind, d.kind))
    t.fail("distribution", "\"" + kind + "\" is not allowed; use " + choices(sampling::kDistributionNames));
  auto positive = [&](std::string_view key) {
    const double v = t.required_number(key);
    if (!(v > 0.0)) t.fail(key, "must be > 0");
    return v;
  };
  switch (d.kind) {
    case sampling::Distribution::Kind::normal:
      d.mean = t.number("mean", 0.0);
      d.std = positive("std");
      break;
    case sampling::Distribution::Kind::truncated_normal: {
      d.mean = t.number("mean", 0.0);
      d.std = positive("std");
      d.lower = t.required_number("lower");
      d.upper = t.required_number("upper");
      if (!(d.lower < d.upper)) t.fail("upper", "must be greater than 'lower'");
      sampling::Distribution untruncated = d;
      untruncated.kind = sampling::Distribution::Kind::normal;
      if (!(untruncated.cdf(d.upper) - untruncated.cdf(d.lower) > 1e-12))
        t.fail("lower", "the interval [lower, upper] holds no probability of the normal");
      break;
    }
    case sampling::Distribution::Kind::uniform:
      d.lower = t.required_number("lower");
      d.upper = t.required_number("upper");
      if (!(d.lower < d.upper)) t.fail("upper", "must be greater than 'lower'");
      break;
    case sampling::Distribution::Kind::lognormal:
      d.mu = t.number("mu", 0.0);
      d.sigma = positive("sigma");
      break;
  }
  return d;
}

// [ensemble] per_sample = ["final", "max", ...]: which reductions to store.
std::vector<Reduction> read_per_sample(const TomlView& t) {
  const toml::node* node = t.table().get("per_sample");
  const toml::array* list = node ? node->as_array() : nullptr;
  if (!list) t.fail("per_sample", "expected an array of reductions: " + choices(kReductionNames));
  std::vector<Reduction> out;
  for (const toml::node& e : *list) {
    Reduction r{};
    const auto text = e.value<std::string>();
    if (!text || !parse_in(kReductionNames, *text, r))
      t.fail_at(&e, "per_sample", "not a reduction; allowed: " + choices(kReductionNames));
    if (std::find(out.begin(), out.end(), r) != out.end())
      t.fail_at(&e, "per_sample", "\"" + *text + "\" is listed twice");
    out.push_back(r);
  }
  // Stored in the catalogue's order, whatever the order given.
  std::sort(out.begin(), out.end());
  return out;
}

// A response's limit and which side of it fails.
void read_limit(const TomlView& t, Response& r) {
  const auto fail_if = t.string("fail_if");
  if (t.has("limit") && !fail_if)
    t.fail("limit", "a limit needs fail_if = \"above\" or \"below\" (which side is failure)");
  if (fail_if) {
    if (!parse_in(kFailIfNames, *fail_if, r.fail_if))
      t.fail("fail_if", "\"" + *fail_if + "\" is not allowed; use " + choices(kFailIfNames));
    if (!t.has("limit")) t.fail("fail_if", "needs a limit = value (in " + r.units + ")");
    r.limit = t.required_number("limit");
  }
}

// One [[ensemble.response]]: a named scalar of one recorded column.
Response read_response(const TomlView& t, const Job& job, const ColumnLayout& layout) {
  t.check_keys({"name", "quantity", "column", "reduce", "time", "threshold", "limit", "fail_if"});
  Response r;
  r.name = t.required_string("name");
  const bool control = std::any_of(r.name.begin(), r.name.end(),
                                   [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; });
  if (r.name.empty() || control || r.name.find('/') != std::string::npos || r.name == "." || r.name == "..")
    t.fail("name", "must be a non-empty name without '/' or control characters (it names an HDF5 group)");
  r.quantity = t.required_string("quantity");
  const auto q = std::find(layout.quantity.begin(), layout.quantity.end(), r.quantity);
  if (q == layout.quantity.end()) {
    std::string recorded;
    for (const auto& name : layout.quantity) recorded += " " + name;
    const std::vector<std::string_view> names(layout.quantity.begin(), layout.quantity.end());
    t.fail("quantity", "\"" + r.quantity + "\" is not recorded; use one of:" + recorded +
                           " (or add it to [output] quantities)" + did_you_mean(r.quantity, names));
  }
  const auto qi = static_cast<std::size_t>(q - layout.quantity.begin());
  r.column = t.required_string("column");
  const auto& names = layout.names[qi];
  const auto c = std::find(names.begin(), names.end(), r.column);
  if (c == names.end()) {
    std::vector<std::string_view> allowed(names.begin(), names.end());
    std::string listed;
    for (std::size_t k = 0; k < std::min<std::size_t>(names.size(), 12); ++k) listed += " " + names[k];
    if (names.size() > 12) listed += " ...";
    t.fail("column", "\"" + r.column + "\" is not a column of " + r.quantity + "; its columns:" + listed +
                         did_you_mean(r.column, allowed));
  }
  const auto ci = static_cast<std::size_t>(c - names.begin());
  r.column_index = layout.offset[qi] + ci;
  const std::string reduce = t.required_string("reduce");
  if (!parse_in(kResponseReduceNames, reduce, r.reduce))
    t.fail("reduce", "\"" + reduce + "\" is not allowed; use " + choices(kResponseReduceNames));
  using Reduce = Response::Reduce;
  const bool crossing = r.reduce == Reduce::first_time_above || r.reduce == Reduce::first_time_below;
  r.units = crossing ? "s" : column_unit(layout, qi, ci);
  const std::vector<double>& times = job.request.output_times;
  if (r.reduce == Reduce::at_time) {
    r.time = t.required_number("time");
    if (!(r.time >= times.front() && r.time <= times.back()))
      t.fail("time", format_number(r.time) + " s is outside the output times [" + format_number(times.front()) + ", " +
                         format_number(times.back()) + "] s");
  } else if (t.has("time")) {
    t.fail("time", "only used with reduce = \"at_time\"");
  }
  if (crossing)
    r.threshold = t.required_number("threshold");
  else if (t.has("threshold"))
    t.fail("threshold", "only used with reduce = \"first_time_above\" or \"first_time_below\"");
  read_limit(t, r);
  return r;
}

}  // namespace

double per_sample_bytes(const Job& job, const EnsembleSpec& spec) {
  const std::size_t columns = column_layout(job.model, job.output).columns;
  return 8.0 * static_cast<double>(spec.runs) * static_cast<double>(columns) *
         static_cast<double>(spec.per_sample.size());
}

double answers_bytes(const EnsembleSpec& spec) {
  if (spec.responses.empty()) return 0.0;
  // The table (inputs, responses, status) and, while one response is
  // analysed, its rows, their ranks, the standardised rank matrix and its QR
  // copy: about 4 D more doubles per sample.
  const double d = spec.input_dimensions();
  return 8.0 * static_cast<double>(spec.runs) * (d + static_cast<double>(spec.responses.size()) + 1.0 + 4.0 * d + 2.0);
}

double stored_trajectory_bytes(const Job& job, const EnsembleSpec& spec) {
  const std::size_t columns = column_layout(job.model, job.output).columns;
  return 8.0 * static_cast<double>(spec.store_trajectories) * static_cast<double>(job.request.output_times.size()) *
         static_cast<double>(columns);
}

double statistics_bytes(const Job& job, const EnsembleSpec& spec) {
  const std::size_t columns = column_layout(job.model, job.output).columns;
  const double entries = static_cast<double>(job.request.output_times.size()) * static_cast<double>(columns);
  // The accumulator, the nominal and pilot range (3 doubles), one sample's
  // trajectory and, at worst (one rank), every pilot trajectory.
  return statistics::EnsembleStatistics::memory_bytes(entries, spec.histogram_bins) +
         entries * (3 * 8.0 + 8.0 * (1.0 + static_cast<double>(spec.pilot_samples)));
}

unsigned EnsembleSpec::input_dimensions() const {
  unsigned d = 0;
  for (const sampling::Perturbation& p : perturbations) d += static_cast<unsigned>(p.dimensions());
  return d;
}

std::vector<std::string> EnsembleSpec::input_names() const {
  std::vector<std::string> names;
  for (const sampling::Perturbation& p : perturbations)
    for (auto& n : p.input_names()) names.push_back(n);
  return names;
}

unsigned EnsembleSpec::unit_count() const {
  return sobol_units.empty() ? input_dimensions() : static_cast<unsigned>(sobol_units.size());
}

std::vector<std::string> EnsembleSpec::unit_names() const {
  if (!grouped) return input_names();
  std::vector<std::string> names;
  for (const SobolUnit& unit : sobol_units) names.push_back(unit.name);
  return names;
}

std::vector<std::string> EnsembleSpec::unit_inputs() const {
  const std::vector<std::string> inputs = input_names();
  std::vector<std::string> members;
  for (const SobolUnit& unit : sobol_units) {
    std::string listed;
    for (unsigned d : unit.inputs) listed += (listed.empty() ? "" : ", ") + inputs[d];
    members.push_back(listed);
  }
  return members;
}

std::vector<unsigned> EnsembleSpec::unit_of_input() const {
  std::vector<unsigned> unit(input_dimensions());
  for (unsigned d = 0; d < unit.size(); ++d) unit[d] = d;
  for (unsigned u = 0; u < sobol_units.size(); ++u)
    for (unsigned d : sobol_units[u].inputs) unit[d] = u;
  return unit;
}

std::vector<std::string> EnsembleSpec::input_units() const {
  std::vector<std::string> units;
  for (const sampling::Perturbation& p : perturbations)
    for (int k = 0; k < p.dimensions(); ++k)
      units.push_back(p.mode == Mode::scale && p.kind != Kind::orientation && p.kind != Kind::rotation ? "1"
                                                                                                       : p.si_unit);
  return units;
}

sampling::Perturbation read_target(const TomlView& t, const ModelDefinition& model) {
  sampling::Perturbation p;
  p.target = t.required_string("target");
  try {
    sampling::aim(p, model);
  } catch (const sampling::TargetError& e) {
    t.fail("target", e.what());
  }
  const std::string mode = t.string("mode").value_or("set");
  if (!parse_in(sampling::kModeNames, mode, p.mode))
    t.fail("mode", "\"" + mode + "\" is not allowed; use " + choices(sampling::kModeNames));
  return p;
}

namespace {

// samples, seed, design and the statistics' settings.
void read_settings(const TomlView& t, EnsembleSpec& s) {
  if (auto design = t.string("design"); design && !sampling::parse_design(*design, s.design))
    t.fail("design", "\"" + *design + "\" is not allowed; use " + choices(sampling::kDesignNames));
  if (designs::rules_of(s.design).takes_samples()) {
    const auto samples = t.integer("samples");
    if (!samples) t.fail("samples", "missing required field: the number of samples (integer >= 1)");
    if (*samples < 1) t.fail("samples", "must be at least 1");
    s.samples = static_cast<std::uint64_t>(*samples);
  }
  if (auto seed = t.integer("seed")) {
    if (*seed < 0) t.fail("seed", "must be a non-negative integer");
    s.seed = static_cast<std::uint64_t>(*seed);
  }
  if (auto q = t.numbers("quantiles")) {
    if (q->empty()) t.fail("quantiles", "list at least one probability in (0, 1)");
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
  if (auto block = t.integer("block_size")) {
    if (*block < 1) t.fail("block_size", "must be at least 1");
    s.block_size = static_cast<std::uint64_t>(*block);
  }
}

sampling::Perturbation read_perturbation(const TomlView& p, const Job& job) {
  p.check_keys({"target", "distribution", "mean", "std", "lower", "upper", "mu", "sigma", "mode", "unit"});
  sampling::Perturbation pert = read_target(p, job.definition);
  if ((pert.kind == Kind::orientation || pert.kind == Kind::rotation) && p.has("mode"))
    p.fail("mode", "not used for this target (a rotation is always composed with the nominal orientation)");
  if (pert.kind == Kind::parameter_list && pert.mode == Mode::scale)
    p.fail("mode", "a list of phases is set or added to, not scaled; use \"set\" or \"add\"");
  if (pert.kind == Kind::parameter_list && !p.has("distribution")) {
    // Random phases: each uniform on [0, 2 pi), the sea state's own randomness.
    for (const char* key : {"mean", "std", "lower", "upper", "mu", "sigma", "unit", "mode"})
      if (p.has(key))
        p.fail(key,
               "without 'distribution' every entry is uniform on [0, 2 pi) rad, set; give a distribution "
               "(and its unit) to change that");
    pert.distribution.kind = sampling::Distribution::Kind::uniform;
    pert.distribution.lower = 0.0;
    pert.distribution.upper = 2.0 * std::numbers::pi;
    return pert;
  }
  if (pert.kind == Kind::parameter_list && !p.has("mode"))
    p.fail("distribution",
           "with a distribution, say what it does to each phase: mode = \"add\" (a spread about the "
           "nominal phases) or \"set\" (every phase drawn from it: a narrow one makes the components "
           "add up in phase, one freak wave)");
  pert.unit = read_unit(p, pert);
  pert.distribution = read_distribution(p);
  return pert;
}

// Every design's own table is refused in another design's job.
void refuse_other_tables(const TomlView& t, const EnsembleSpec& s) {
  for (const auto& [design, name] : sampling::kDesignNames) {
    const std::string_view table = designs::rules_of(design).table();
    if (design != s.design && !table.empty() && t.has(table))
      t.fail(table, "[ensemble." + std::string(table) + "] is only for design = \"" + std::string(name) + "\"");
  }
}

// The number of runs the design makes (its rules: saltelli N (U + 2), ...),
// within what the exact sums hold.
void count_runs(const TomlView& t, EnsembleSpec& s) {
  designs::rules_of(s.design).read_runs(t, s, kMaxRuns);
  refuse_more_runs_than(t, s.runs, kMaxRuns);
  s.pilot_samples = std::min(s.pilot_samples, designs::rules_of(s.design).first_wave_runs(s));
}

// Per-sample reductions, the named responses, the bootstrap.
void read_answers(const TomlView& t, const Job& job, EnsembleSpec& s) {
  if (t.has("per_sample")) s.per_sample = read_per_sample(t);
  const ColumnLayout layout = column_layout(job.model, job.output);
  for (const TomlView& r : t.table_array("response")) {
    s.responses.push_back(read_response(r, job, layout));
    for (std::size_t k = 0; k + 1 < s.responses.size(); ++k)
      if (s.responses[k].name == s.responses.back().name)
        r.fail("name", "response \"" + s.responses.back().name + "\" is defined twice; names must be unique");
  }
  if (auto b = t.integer("bootstrap_resamples")) {
    if (*b < 0 || *b > 100000) t.fail("bootstrap_resamples", "must be from 0 to 100000");
    s.bootstrap_resamples = static_cast<int>(*b);
  }
}

void read_stored_trajectories(const TomlView& t, const Job& job, EnsembleSpec& s) {
  const auto m = t.integer("store_trajectories");
  if (!m) return;
  if (*m < 0) t.fail("store_trajectories", "must be >= 0 (samples 0 .. M-1 are stored)");
  s.store_trajectories = static_cast<std::uint64_t>(*m);
  if (s.store_trajectories > s.runs)
    t.fail("store_trajectories", "is more than the " + std::to_string(s.runs) + " samples");
  // Each stored trajectory travels to rank 0 with its record, a block of
  // them at a time: that block must fit in memory.
  const double one =
      stored_trajectory_bytes(job, s) / static_cast<double>(std::max<std::uint64_t>(s.store_trajectories, 1));
  const double batch_gib = one * static_cast<double>(s.block_size) / (1024.0 * 1024.0 * 1024.0);
  if (s.store_trajectories > 0 && batch_gib > 1.0)
    t.fail("store_trajectories", "one trajectory is " + format_number(std::round(one / (1024.0 * 1024.0))) +
                                     " MiB and a block of " + std::to_string(s.block_size) + " would need " +
                                     format_number(std::round(batch_gib)) +
                                     " GiB in memory; at most 1 GiB: use fewer output times or "
                                     "quantities, or block_size = 1");
}

// [ensemble.stop]: which response, which targets, how often to check.
void read_stop(const TomlView& parent, EnsembleSpec& s) {
  const auto section = parent.subtable("stop");
  if (!section) return;
  const TomlView& t = *section;
  t.check_keys({"response", "exceedance_cov", "mean_sem", "mean_relative_sem", "every"});
  const designs::DesignRules& rules = designs::rules_of(s.design);
  if (const std::string_view why = rules.why_no_stopping_rule(); !why.empty()) t.fail("response", std::string(why));
  StopRule rule;
  const std::size_t index = named_response(t, s);
  const Response& response = s.responses[index];
  const std::string& name = response.name;
  rule.response = index;
  auto target = [&t](std::string_view key) -> std::optional<double> {
    const auto v = t.number(key);
    if (v && !(*v > 0.0 && std::isfinite(*v))) t.fail(key, "must be a positive number");
    return v;
  };
  rule.exceedance_cov = target("exceedance_cov");
  rule.mean_sem = target("mean_sem");
  rule.mean_relative_sem = target("mean_relative_sem");
  if (!rule.exceedance_cov && !rule.mean_sem && !rule.mean_relative_sem)
    t.fail("response", "give at least one target: exceedance_cov, mean_sem or mean_relative_sem");
  if (rule.exceedance_cov && !response.has_limit())
    t.fail("exceedance_cov", "response \"" + name + "\" has no limit (add limit and fail_if to it)");
  const auto every = t.integer("every");
  if (!every) t.fail("every", "missing: the check interval in samples (saltelli: in base samples, whole blocks)");
  if (*every < 1) t.fail("every", "must be at least 1");
  const std::uint64_t unit = rules.runs_per_step(s);
  if (static_cast<std::uint64_t>(*every) > s.runs / unit)
    t.fail("every", "checks every " + std::to_string(*every) + (unit > 1 ? " blocks" : " samples") +
                        ", more than the ensemble makes at most (" + std::to_string(s.runs / unit) +
                        (unit > 1 ? " blocks)" : ")"));
  rule.every = static_cast<std::uint64_t>(*every) * unit;
  if (rule.every > s.runs)
    t.fail("every", "checks every " + std::to_string(rule.every) + " runs, more than the " + std::to_string(s.runs) +
                        " the ensemble makes at most");
  s.stop = rule;
}

// What rank 0 and every rank must hold, within 8 GiB each.
void check_memory(const TomlView& t, const Job& job, const EnsembleSpec& s) {
  if (!s.responses.empty()) {
    const double gib = answers_bytes(s) / (1024.0 * 1024.0 * 1024.0);
    if (gib > 8.0)
      t.fail("response", "the responses and inputs of " + std::to_string(s.runs) + " samples would need " +
                             format_number(std::round(gib)) + " GiB on rank 0; at most 8: use fewer samples");
  }
  const double gib = statistics_bytes(job, s) / (1024.0 * 1024.0 * 1024.0);
  if (gib > 8.0)
    t.fail("histogram_bins", "the statistics would need " + format_number(std::round(gib)) +
                                 " GiB per rank (output times x columns x bins); at most 8: use "
                                 "fewer bins, output times or quantities");
}

// [ensemble]'s keys: its own, and every design's table.
std::vector<std::string_view> ensemble_keys() {
  std::vector<std::string_view> keys{
      "samples",    "seed",         "design",     "quantiles", "histogram_bins",     "pilot_samples",
      "block_size", "perturbation", "per_sample", "response",  "store_trajectories", "bootstrap_resamples",
      "stop",       "group",        "correlation"};
  for (const auto& [design, name] : sampling::kDesignNames)
    if (const std::string_view table = designs::rules_of(design).table(); !table.empty()) keys.push_back(table);
  return keys;
}

}  // namespace

// The exact sums hold 2^26 extreme samples (d / S at its 2^20 limit, squared
// with 60 fraction bits: 2^100 each, 2^126 in all); 32-bit Sobol points and
// histogram counters would allow more.
void refuse_more_runs_than(const TomlView& t, std::uint64_t runs, std::uint64_t max_runs) {
  if (runs > max_runs)
    t.fail("samples", std::to_string(runs) + " samples: at most " + std::to_string(max_runs) +
                          " (2^26, so that the exact 128-bit sums cannot overflow); split larger studies into "
                          "several ensembles with different seeds");
}

std::size_t named_response(const TomlView& t, const EnsembleSpec& s) {
  const std::string name = t.required_string("response");
  for (std::size_t r = 0; r < s.responses.size(); ++r)
    if (s.responses[r].name == name) return r;
  t.fail("response", "\"" + name + "\" is not the name of an [[ensemble.response]]");
}

EnsembleSpec read_ensemble(const Job& job) {
  const TomlView root(root_table(job.document), "", job.file);
  const auto section = root.subtable("ensemble");
  if (!section)
    throw JobError(job.file, 0, 0, "ensemble",
                   "missing [ensemble] section: give at least samples = N (and seed, perturbations)");
  const TomlView& t = *section;
  t.check_keys(ensemble_keys());
  EnsembleSpec s;
  read_settings(t, s);
  refuse_other_tables(t, s);
  for (const TomlView& p : t.table_array("perturbation")) s.perturbations.push_back(read_perturbation(p, job));
  read_groups(t, s);
  read_correlations(t, s);
  read_answers(t, job, s);
  count_runs(t, s);
  read_stop(t, s);
  read_stored_trajectories(t, job, s);
  check_memory(t, job, s);
  return s;
}

}  // namespace treedyn
