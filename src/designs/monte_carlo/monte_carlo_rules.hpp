// design = "monte_carlo": its DesignRules (designs/design_rules.hpp).
#pragma once

#include "designs/design_rules.hpp"

namespace treedyn::designs {

const DesignRules& monte_carlo_rules();

}  // namespace treedyn::designs
