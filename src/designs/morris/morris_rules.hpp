// design = "morris": its DesignRules (designs/design_rules.hpp).
#pragma once

#include "designs/design_rules.hpp"

namespace treedyn::designs {

const DesignRules& morris_rules();

}  // namespace treedyn::designs
