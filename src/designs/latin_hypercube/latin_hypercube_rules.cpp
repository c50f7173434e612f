// design = "latin_hypercube": every input's range in N strata, each hit once,
// so run k depends on N and a prefix of the runs is not a design.
#include "designs/latin_hypercube/latin_hypercube_rules.hpp"

#include "designs/latin_hypercube/latin_hypercube_points.hpp"

namespace treedyn::designs {

namespace {
class LatinHypercubeRules final : public DesignRules {
 public:
  sampling::Design design() const override { return sampling::Design::latin_hypercube; }
  std::unique_ptr<sampling::RunPoints> points(const sampling::PointsSpec& spec) const override {
    return latin_hypercube_points(spec);
  }
  bool nested_prefixes() const override { return false; }
  std::string_view why_no_stopping_rule() const override {
    return "a stopping rule needs a design whose prefixes are designs (monte_carlo, sobol, saltelli); the first n "
           "samples of a latin_hypercube are not one";
  }
  void print_runs(std::ostream& out, const EnsembleSpec&) const override {
    out << "  latin_hypercube: sample k depends on N too, so prefixes are not nested samples "
           "(convergence by prefix is not meaningful)\n";
  }
};
}  // namespace

const DesignRules& latin_hypercube_rules() {
  static const LatinHypercubeRules rules;
  return rules;
}

}  // namespace treedyn::designs
