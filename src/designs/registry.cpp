// Every design's rules, by design: a new design adds its line here.
#include <array>
#include <stdexcept>

#include "designs/latin_hypercube/latin_hypercube_rules.hpp"
#include "designs/monte_carlo/monte_carlo_rules.hpp"
#include "designs/morris/morris_rules.hpp"
#include "designs/saltelli/saltelli_rules.hpp"
#include "designs/sobol/sobol_rules.hpp"
#include "designs/subset_simulation/subset_simulation_rules.hpp"

namespace treedyn::designs {

const DesignRules& rules_of(sampling::Design design) {
  using Rules = const DesignRules& (*)();
  static constexpr std::array<Rules, 6> kRules{monte_carlo_rules, latin_hypercube_rules,   sobol_rules,
                                               saltelli_rules,    subset_simulation_rules, morris_rules};
  for (Rules rules : kRules)
    if (rules().design() == design) return rules();
  throw std::logic_error("a design without rules (designs/registry.cpp)");
}

}  // namespace treedyn::designs
