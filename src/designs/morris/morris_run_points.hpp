// design = "morris": run s of trajectory t is run t (U + 1) + s. Radial
// steps: A_t, then A_t with unit s - 1 from B_t (Saltelli's A and B,
// sampling/design.hpp); trajectories: MorrisPoints (morris_points.hpp).
#pragma once

#include <memory>

#include "sampling/run_points.hpp"

namespace treedyn::designs {

// Radial unless spec.morris says trajectories. Throws std::invalid_argument
// beyond Boost's Sobol' tables or 2^32 - 1 radial trajectories.
std::unique_ptr<sampling::RunPoints> morris_run_points(const sampling::PointsSpec& spec);

}  // namespace treedyn::designs
