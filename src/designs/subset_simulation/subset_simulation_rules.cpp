// design = "subset_simulation": level 0 is a Monte-Carlo sample; the later
// levels' runs are Markov chains conditioned on the failure (subset_simulation.hpp).
#include "designs/subset_simulation/subset_simulation_rules.hpp"

#include <algorithm>
#include <cmath>

#include "common/format.hpp"
#include "designs/monte_carlo/monte_carlo_points.hpp"
#include "designs/subset_simulation/read_subset.hpp"
#include "job/ensemble_spec.hpp"

namespace treedyn::designs {

namespace {
class SubsetSimulationRules final : public DesignRules {
 public:
  sampling::Design design() const override { return sampling::Design::subset_simulation; }
  // Level 0; the later levels' runs come from their chains.
  std::unique_ptr<sampling::RunPoints> points(const sampling::PointsSpec& spec) const override {
    return monte_carlo_points(spec);
  }
  std::string_view table() const override { return "subset"; }
  void read_runs(const TomlView& ensemble, EnsembleSpec& s, std::uint64_t max_runs) const override {
    read_subset(ensemble, s, max_runs);
  }
  std::uint64_t first_wave_runs(const EnsembleSpec& s) const override { return s.samples; }  // level 0
  bool follows_records(const EnsembleSpec& s, std::uint64_t k) const override { return k >= s.samples; }
  std::uint64_t answered_runs(const EnsembleSpec& s, std::uint64_t runs) const override {
    return std::min(runs, s.samples);
  }
  bool answers_probability(const EnsembleSpec& s, std::size_t r) const override {
    return s.subset && s.subset->response == r;
  }
  std::string_view why_no_stopping_rule() const override {
    return "a stopping rule needs a design whose prefixes are designs (monte_carlo, sobol, saltelli); "
           "subset_simulation sets its own runs (samples per level, levels)";
  }
  std::string_view runs_note() const override {
    return " (subset_simulation: at most; level 0, then the later levels' chains until a threshold reaches the limit)";
  }
  std::string_view counted_runs_note() const override { return "subset_simulation: level 0, the Monte-Carlo level"; }
  std::string_view statistics_note() const override {
    return "; subset_simulation: level 0 alone (samples 0 .. N-1), an unbiased Monte-Carlo sample; the later "
           "levels' runs are conditional samples and left out (they are in /samples)";
  }
  void print_runs(std::ostream& out, const EnsembleSpec& s) const override;
};

// Runs per level, chains, and the runs the simulation makes, which depend
// on P: N (1 + (1 - p0) m) when level m is the first whose threshold
// reaches the limit, P near p0^(m + 1).
void SubsetSimulationRules::print_runs(std::ostream& out, const EnsembleSpec& s) const {
  const double p0 = s.subset->level_probability;
  const double n = static_cast<double>(s.samples);
  out << "  subset_simulation: " << s.samples << " runs per level, level_probability " << format_number(p0) << " ("
      << static_cast<std::uint64_t>(std::llround(n * p0)) << " chains of " << std::llround(1.0 / p0)
      << " states), at most " << s.subset->max_levels << " levels after level 0, for P("
      << s.responses[s.subset->response].name << " beyond its limit) down to about "
      << format_digits(std::pow(p0, s.subset->max_levels + 1), 2) << "\n";
  out << "    the runs depend on P (the levels until a threshold reaches the limit):";
  for (int m = 1; m <= s.subset->max_levels; ++m)
    out << (m > 1 ? ";" : "") << " P ~ " << format_digits(std::pow(p0, m + 1), 2) << ": "
        << std::llround(n * (1.0 + (1.0 - p0) * m));
  out << " runs (at most " << s.runs << ")\n";
}
}  // namespace

const DesignRules& subset_simulation_rules() {
  static const SubsetSimulationRules rules;
  return rules;
}

}  // namespace treedyn::designs
