// design = "saltelli": run j (U + 2) + r is A_j, B_j or AB_u,j
// (sampling/design.hpp: saltelli_place, saltelli_point), A and B from one
// scrambled Sobol' sequence over 2D dimensions.
#pragma once

#include <memory>

#include "sampling/run_points.hpp"

namespace treedyn::designs {

// Throws std::invalid_argument beyond Boost's tables or 2^32 - 1 base points.
std::unique_ptr<sampling::RunPoints> saltelli_points(const sampling::PointsSpec& spec);

}  // namespace treedyn::designs
