// design = "morris": trajectories of U + 1 runs, each step moving one unit
// (an input or a group), for the elementary effects (morris_effects.hpp).
#include "designs/morris/morris_rules.hpp"

#include "designs/morris/morris_run_points.hpp"
#include "designs/morris/read_morris.hpp"
#include "job/ensemble_spec.hpp"

namespace treedyn::designs {

namespace {
class MorrisRules final : public DesignRules {
 public:
  sampling::Design design() const override { return sampling::Design::morris; }
  std::unique_ptr<sampling::RunPoints> points(const sampling::PointsSpec& spec) const override {
    return morris_run_points(spec);
  }
  std::string_view table() const override { return "morris"; }
  bool takes_samples() const override { return false; }  // trajectories, in [ensemble.morris]
  void read_runs(const TomlView& ensemble, EnsembleSpec& s, std::uint64_t max_runs) const override {
    read_morris(ensemble, s, max_runs);
  }
  std::uint64_t runs_per_step(const EnsembleSpec& s) const override { return s.unit_count() + 1u; }
  // A trajectory's first run; the others each move one unit from the run before.
  bool independent_draw(const EnsembleSpec& s, std::uint64_t k) const override {
    return k % (s.unit_count() + 1u) == 0;
  }
  std::string_view why_no_stopping_rule() const override {
    return "morris screens with all its trajectories: a stopping rule on a response's mean or exceedance does not "
           "apply (choose the trajectories; the page says whether the ranking is resolved)";
  }
  bool takes_groups() const override { return true; }
  bool list_input_is_one_factor() const override { return true; }  // a sea's phases
  std::string_view why_no_correlations() const override {
    return "Morris' elementary effects move one input (or group) at a time: with correlated inputs a step in one "
           "moves the others, and the effects mix";
  }
  std::string_view runs_note() const override {
    return " (morris: trajectories x (D + 1) runs, or x (G + 1) with groups)";
  }
  std::string_view counted_runs_note() const override { return "morris: each trajectory's first run"; }
  std::string_view samples_description() const override {
    return "one row per run, by sample index 0 .. samples-1; morris: row t (U + 1) + s is run s of trajectory t: "
           "radial, run 0 with unit s - 1 (an input or a group) from an independent point; trajectories, run s - 1 "
           "with that unit moved by 1/2 in u; morris_trajectories, morris_steps (morris_levels) and morris_block "
           "U + 1 are root attributes";
  }
  std::string_view statistics_note() const override {
    return "; morris: over every run of every trajectory (sem assumes independent samples: use each trajectory's "
           "first row of /samples for it)";
  }
  std::string_view sensitivity_description() const override {
    return "rank measures over each trajectory's first run; Morris' measures (morris_*) from every step";
  }
  std::vector<DesignAttribute> attributes(const EnsembleSpec& s) const override;
  void print_runs(std::ostream& out, const EnsembleSpec& s) const override;
};

std::vector<DesignAttribute> MorrisRules::attributes(const EnsembleSpec& s) const {
  std::vector<DesignAttribute> a{{"morris_trajectories", static_cast<long long>(s.samples)},
                                 {"morris_steps", std::string(s.morris->radial ? "radial" : "trajectories")}};
  if (!s.morris->radial) a.push_back({"morris_levels", static_cast<long long>(s.morris->levels)});
  a.push_back({"morris_block", static_cast<long long>(s.unit_count() + 1)});
  return a;
}

void MorrisRules::print_runs(std::ostream& out, const EnsembleSpec& s) const {
  const char* u = s.grouped ? "G" : "D";
  out << "  morris: r = " << s.samples << " trajectories of (" << u << " + 1) = " << s.unit_count() + 1
      << " runs = " << s.runs << " runs; ";
  if (s.morris->radial)
    out << "radial steps: run t (" << u << " + 1) of trajectory t is A_t, run t (" << u << " + 1) + s is A_t with "
        << (s.grouped ? "group" : "input") << " s - 1 from B_t (scrambled Sobol' points A and B, as Saltelli's)\n";
  else
    out << s.morris->levels << " levels (u = (l + 1/2) / " << s.morris->levels << "); run t (" << u
        << " + 1) + s of trajectory t moves one " << (s.grouped ? "group" : "input") << " by Delta = 1/2 in u\n";
}
}  // namespace

const DesignRules& morris_rules() {
  static const MorrisRules rules;
  return rules;
}

}  // namespace treedyn::designs
