// design = "saltelli": blocks of A_j, B_j and AB_u,j per base point j
// (sampling/design.hpp), for the Sobol' indices of independent inputs.
#include "designs/saltelli/saltelli_rules.hpp"

#include <string>

#include "designs/saltelli/saltelli_points.hpp"
#include "job/ensemble_spec.hpp"
#include "job/toml_view.hpp"

namespace treedyn::designs {

namespace {
class SaltelliRules final : public DesignRules {
 public:
  sampling::Design design() const override { return sampling::Design::saltelli; }
  std::unique_ptr<sampling::RunPoints> points(const sampling::PointsSpec& spec) const override {
    return saltelli_points(spec);
  }
  void read_runs(const TomlView& ensemble, EnsembleSpec& s, std::uint64_t max_runs) const override;
  std::uint64_t runs_per_step(const EnsembleSpec& s) const override { return s.saltelli_block(); }
  // The AB_u rows repeat all of A_j's inputs but unit u's: each is
  // distributed like the inputs, but not independently of A_j.
  bool independent_draw(const EnsembleSpec& s, std::uint64_t k) const override {
    return sampling::saltelli_place(k, s.unit_count()).role != sampling::SaltelliRole::ab;
  }
  bool takes_groups() const override { return true; }
  std::string_view why_no_correlations() const override {
    return "Saltelli's Sobol' indices assume independent inputs: a correlated design would give wrong indices";
  }
  std::string_view runs_note() const override {
    return " (saltelli: samples x (D + 2) runs, or x (G + 2) with groups)";
  }
  std::string_view counted_runs_note() const override { return "saltelli: the A and B runs"; }
  std::string_view samples_description() const override {
    return "one row per run, by sample index 0 .. samples-1; saltelli: row j (U + 2) + r is A_j (r = 0), B_j (r = "
           "1), AB_u,j (r = 2 + u: A_j with unit u's inputs from B_j; a unit is one input, or a group with "
           "[[ensemble.group]]); base_samples N and saltelli_block U + 2 are root attributes";
  }
  std::string_view statistics_note() const override {
    return "; saltelli: over every run, the correlated AB_i rows included (sem assumes independent samples: use "
           "the A and B rows of /samples for it)";
  }
  std::string_view sensitivity_description() const override {
    return "rank measures over the A and B runs; Sobol' indices from all blocks";
  }
  std::vector<DesignAttribute> attributes(const EnsembleSpec& s) const override {
    return {{"saltelli_block", static_cast<long long>(s.saltelli_block())}};
  }
  void print_runs(std::ostream& out, const EnsembleSpec& s) const override;
};

// N (U + 2) runs, A and B on 2D Sobol' dimensions.
void SaltelliRules::read_runs(const TomlView& t, EnsembleSpec& s, std::uint64_t max_runs) const {
  const unsigned d = s.input_dimensions();
  if (d == 0) t.fail("design", "saltelli needs at least one [[ensemble.perturbation]] (the inputs to rank)");
  if (2 * d > 1000)
    t.fail("perturbation", "saltelli supports at most 500 input dimensions (2D Sobol dimensions); this job has " +
                               std::to_string(d) + " (a sea state's phases count one per component)");
  const std::string block = s.grouped ? "(G + 2)" : "(D + 2)";
  if (s.samples > max_runs / s.saltelli_block())
    t.fail("samples", "saltelli makes samples x " + block + " = " + std::to_string(s.samples) + " x " +
                          std::to_string(s.saltelli_block()) + " runs; at most " + std::to_string(max_runs) +
                          " (2^26, so that the exact 128-bit sums cannot overflow): use at most " +
                          std::to_string(max_runs / s.saltelli_block()));
  s.runs = s.samples * s.saltelli_block();
}

void SaltelliRules::print_runs(std::ostream& out, const EnsembleSpec& s) const {
  if (!s.grouped)
    out << "  saltelli: base size N = " << s.samples << ", N (D + 2) = " << s.samples << " x " << s.saltelli_block()
        << " = " << s.runs << " runs; sample j (D + 2) + r is A_j (r = 0), B_j (r = 1), AB_i,j (r = 2 + i)\n";
  else
    out << "  saltelli with " << s.unit_count() << " groups: base size N = " << s.samples
        << ", N (G + 2) = " << s.samples << " x " << s.saltelli_block() << " = " << s.runs
        << " runs; sample j (G + 2) + r is A_j (r = 0), B_j (r = 1), AB_g,j (r = 2 + g: A_j with group g's "
           "inputs from B_j)\n";
}
}  // namespace

const DesignRules& saltelli_rules() {
  static const SaltelliRules rules;
  return rules;
}

}  // namespace treedyn::designs
