// design = "monte_carlo": independent uniforms per run; every default rule.
#include "designs/monte_carlo/monte_carlo_rules.hpp"

namespace treedyn::designs {

const DesignRules& monte_carlo_rules() {
  static const DefaultRules rules(ensemble::Design::monte_carlo);
  return rules;
}

}  // namespace treedyn::designs
