// design = "latin_hypercube": its DesignRules (designs/design_rules.hpp).
#pragma once

#include "designs/design_rules.hpp"

namespace treedyn::designs {

const DesignRules& latin_hypercube_rules();

}  // namespace treedyn::designs
