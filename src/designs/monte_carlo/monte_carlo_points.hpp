// design = "monte_carlo" (and subset simulation's level 0): independent
// uniforms from a counter-based generator, u_kd = Philox4x64(seed; k, d).
#pragma once

#include <memory>

#include "sampling/run_points.hpp"

namespace treedyn::designs {

std::unique_ptr<sampling::RunPoints> monte_carlo_points(const sampling::PointsSpec& spec);

}  // namespace treedyn::designs
