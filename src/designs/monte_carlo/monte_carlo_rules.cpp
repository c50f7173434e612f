// design = "monte_carlo": independent uniforms per run; every other rule
// the default.
#include "designs/monte_carlo/monte_carlo_rules.hpp"

#include "designs/monte_carlo/monte_carlo_points.hpp"

namespace treedyn::designs {

namespace {
class MonteCarloRules final : public DesignRules {
 public:
  sampling::Design design() const override { return sampling::Design::monte_carlo; }
  std::unique_ptr<sampling::RunPoints> points(const sampling::PointsSpec& spec) const override {
    return monte_carlo_points(spec);
  }
};
}  // namespace

const DesignRules& monte_carlo_rules() {
  static const MonteCarloRules rules;
  return rules;
}

}  // namespace treedyn::designs
