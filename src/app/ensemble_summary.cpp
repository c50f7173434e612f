// What `treedyn-ensemble --check` prints of an [ensemble]: the design, each
// perturbation and what it does, the share of samples outside a
// parameter's valid range, the statistics' and the answers' sizes.
#include <cmath>
#include <cstdio>
#include <optional>

#include "app/model_summary.hpp"
#include "common/format.hpp"
#include "designs/design_rules.hpp"
#include "sampling/invalid_mass.hpp"

namespace treedyn {

namespace {

using Kind = sampling::Perturbation::Kind;
using Mode = sampling::Perturbation::Mode;

std::string bytes_text(double bytes) {
  const char* unit = "KiB";
  double value = bytes / 1024.0;
  if (value >= 1024.0) value /= 1024.0, unit = "MiB";
  if (value >= 1024.0) value /= 1024.0, unit = "GiB";
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%.1f %s", value, unit);
  return buffer;
}

// The share of samples the model would refuse, and a warning above 0.1 %.
void print_invalid_mass(std::ostream& out, const sampling::Perturbation& p, const ModelDefinition& d) {
  const std::optional<sampling::InvalidMass> m = sampling::invalid_mass(p, d);
  if (!m) return;
  char percent[32];
  std::snprintf(percent, sizeof percent, "%.3g %%", 100.0 * m->probability);
  out << "      outside the model's range (" << m->valid << "): " << percent
      << " of the samples, from the distribution's CDF\n";
  if (m->probability > sampling::kInvalidMassWarning)
    out << "      warning: " << percent << " of the samples will fail as invalid models (status 2); narrow the "
        << "distribution, or use truncated_normal (lower bound) or lognormal for a positive quantity\n";
}

// The stopping rule's line: the check interval and each target.
void print_stop_rule(std::ostream& out, const EnsembleSpec& s) {
  if (!s.stop) return;
  const StopRule& rule = *s.stop;
  out << "  stop: checked every " << rule.every << " runs, at the first check point where";
  const char* joint = "";
  auto target = [&](const char* name, const std::optional<double>& v) {
    if (!v) return;
    out << joint << " " << name << " of " << s.responses[rule.response].name << " <= " << format_number(*v);
    joint = " or";
  };
  target("exceedance_cov", rule.exceedance_cov);
  target("mean_sem", rule.mean_sem);
  target("mean_relative_sem", rule.mean_relative_sem);
  out << " (at most " << s.runs << " runs)\n";
}

// A sea state's band is the job's, whatever Tp a sample draws: the share of
// the spectrum's m0 its components keep at the 0.1 % and 99.9 % quantiles of
// a sampled peak period (a peak near the band's edge loses energy silently).
void print_band_share(std::ostream& out, const sampling::Perturbation& p, const ModelDefinition& d) {
  const auto* sea = std::get_if<SeaStateBase>(&d.base.kind);
  if (!sea || p.kind != Kind::parameter) return;
  for (int axis = 0; axis < 3; ++axis) {
    if (d.base.sea[axis].peak_period < 0 || p.first != d.base.sea[axis].peak_period) continue;
    SeaStateAxis a = *sea->axes[axis];
    const double nominal = d.parameters.nominal()[p.first];
    double worst = 1.0;
    out << "      the components' band keeps";
    for (double q : {0.001, 0.999}) {
      const double x = p.distribution.quantile(q) * p.unit;
      a.peak_period = p.mode == Mode::scale ? nominal * x : p.mode == Mode::add ? nominal + x : x;
      if (!(a.peak_period > 0.0)) continue;
      const SeaStateSummary share = summarize(a);
      worst = std::min(worst, share.m0_components / share.m0_spectrum);
      out << (q < 0.5 ? " " : ", ") << format_digits(100.0 * share.m0_components / share.m0_spectrum, 4)
          << " % of m0 at Tp = " << format_digits(a.peak_period, 4) << " s";
    }
    out << " (the 0.1 % and 99.9 % quantiles)\n";
    if (worst < 0.97)
      out << "      warning: below 97 %: widen [base."
          << "xyz"[axis] << "] min_frequency and max_frequency to hold the spectrum at these periods\n";
  }
}

// What each group of a grouped design holds.
void print_groups(std::ostream& out, const EnsembleSpec& s) {
  // Each input's target: a list's entries (a sea state's phases) print as one, TARGET[1..n].
  std::vector<std::pair<const sampling::Perturbation*, int>> owner;
  for (const sampling::Perturbation& p : s.perturbations)
    for (int k = 0; k < p.dimensions(); ++k) owner.emplace_back(&p, k);
  const std::vector<std::string> names = s.input_names();
  for (std::size_t g = 0; g < s.sobol_units.size(); ++g) {
    const SobolUnit& unit = s.sobol_units[g];
    out << "    group " << g << " " << unit.name << ":";
    for (unsigned d : unit.inputs) {
      const auto [p, k] = owner[d];
      if (p->kind != Kind::parameter_list)
        out << " " << names[d];
      else if (k == 0)
        out << " " << p->target << "[1.." << p->entries << "]";
    }
    out << "\n";
  }
}

// Each correlated pair, in both parameters.
void print_correlations(std::ostream& out, const EnsembleSpec& s) {
  if (s.correlations.empty()) return;
  const std::vector<std::string> names = s.input_names();
  out << "  correlated inputs (normal copula on their own marginals):\n";
  for (const sampling::InputCorrelation& c : s.correlations) {
    const double spearman = sampling::spearman_of_normal_copula(c.normal_copula);
    out << "    " << names[c.a] << " ~ " << names[c.b] << ": normal copula rho = " << format_digits(c.normal_copula, 4)
        << ", Spearman " << format_digits(spearman, 4) << (c.given_as_spearman ? " (given)" : "") << "\n";
  }
}

// One perturbation: its distribution and what it does to the model.
void print_perturbation(std::ostream& out, const Job& job, const sampling::Perturbation& p) {
  const auto nominal = job.definition.parameters.nominal();
  out << "  " << p.target << ": " << p.distribution.describe();
  if (p.unit != 1.0) out << " x " << format_number(p.unit) << " (to " << p.si_unit << ")";
  if (p.kind == Kind::orientation)
    out << " per rotation-vector component, rad";
  else if (p.kind == Kind::rotation)
    out << ", rad, composed with the nominal orientation";
  else if (p.kind == Kind::parameter_list)
    out << " per entry (" << p.entries << " inputs), " << (p.mode == Mode::add ? "is added to" : "replaces")
        << " each nominal entry";
  else if (p.entries > 1)
    out << (p.mode == Mode::scale ? " multiplies the matrix"
            : p.mode == Mode::add ? " x E is added to the matrix"
                                  : " x E replaces the matrix");
  else
    out << (p.mode == Mode::scale ? " multiplies"
            : p.mode == Mode::add ? " is added to"
                                  : " replaces")
        << " the nominal "
        << (p.kind == Kind::parameter ? nominal[p.first] / p.factor : job.initial.angular_velocity[p.first][p.axis])
        << " " << p.si_unit;
  out << "\n      " << p.enters << "\n";
  print_invalid_mass(out, p, job.definition);
  print_band_share(out, p, job.definition);
}

}  // namespace

void print_ensemble_summary(std::ostream& out, const Job& job, const EnsembleSpec& s) {
  // An adaptive design makes as many runs as its answers need: `runs` is
  // the most (its print_runs says how many).
  const bool at_most = designs::rules_of(s.design).adaptive(s);
  out << "ensemble: " << (at_most ? "at most " : "") << s.runs
      << (at_most ? " runs (below: how many it makes)" : " samples") << ", seed " << s.seed << ", design "
      << name(s.design) << ", " << s.perturbations.size() << " perturbation" << (s.perturbations.size() == 1 ? "" : "s")
      << " (" << s.input_dimensions() << " sampled inputs)\n";
  designs::rules_of(s.design).print_runs(out, s);
  if (s.grouped) print_groups(out, s);
  print_correlations(out, s);
  print_stop_rule(out, s);
  for (const sampling::Perturbation& p : s.perturbations) print_perturbation(out, job, p);
  out << "statistics: quantiles";
  for (double q : s.quantiles) out << " " << format_number(q);
  out << "; " << s.histogram_bins << " histogram bins; pilot samples 0-" << s.pilot_samples - 1 << "; blocks of "
      << s.block_size << "; about " << format_number(std::round(statistics_bytes(job, s) / (1024.0 * 1024.0)))
      << " MiB per rank\n";
  out << "per sample: ";
  for (std::size_t k = 0; k < s.per_sample.size(); ++k) out << (k ? ", " : "") << name(s.per_sample[k]);
  if (s.per_sample.empty()) out << "no reductions";
  out << " of every column: " << bytes_text(per_sample_bytes(job, s)) << " in the file\n";
  if (s.store_trajectories > 0)
    out << "stored trajectories: samples 0-" << s.store_trajectories - 1 << ", "
        << bytes_text(stored_trajectory_bytes(job, s)) << " in the file\n";
  if (!s.responses.empty())
    out << "answers: about " << bytes_text(answers_bytes(s)) << " on rank 0 for the responses' analysis\n";
  for (const Response& r : s.responses) {
    out << "response " << r.name << ": " << name(r.reduce) << " of " << r.quantity << " " << r.column;
    if (r.reduce == Response::Reduce::at_time) out << " at t = " << format_number(r.time) << " s";
    if (r.reduce == Response::Reduce::first_time_above || r.reduce == Response::Reduce::first_time_below)
      out << ", threshold " << format_number(r.threshold);
    out << " (" << r.units << ")";
    if (r.has_limit())
      out << "; fails " << (r.fail_if == Response::FailIf::above ? "above " : "below ") << format_number(r.limit) << " "
          << r.units;
    out << "\n";
  }
}

}  // namespace treedyn
