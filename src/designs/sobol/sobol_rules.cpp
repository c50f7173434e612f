// design = "sobol": scrambled Sobol' points, whose prefixes are designs too.
#include "designs/sobol/sobol_rules.hpp"

#include "designs/sobol/sobol_points.hpp"
#include "job/ensemble_spec.hpp"
#include "job/toml_view.hpp"

namespace treedyn::designs {

namespace {
class SobolRules final : public DesignRules {
 public:
  sampling::Design design() const override { return sampling::Design::sobol; }
  std::unique_ptr<sampling::RunPoints> points(const sampling::PointsSpec& spec) const override {
    return sobol_points(spec);
  }
  void read_runs(const TomlView& t, EnsembleSpec& s, std::uint64_t) const override {
    if (s.input_dimensions() > 1000) t.fail("perturbation", "sobol supports at most 1000 input dimensions");
    s.runs = s.samples;
  }
};
}  // namespace

const DesignRules& sobol_rules() {
  static const SobolRules rules;
  return rules;
}

}  // namespace treedyn::designs
