// design = "subset_simulation": its DesignRules (designs/design_rules.hpp).
#pragma once

#include "designs/design_rules.hpp"

namespace treedyn::designs {

const DesignRules& subset_simulation_rules();

}  // namespace treedyn::designs
