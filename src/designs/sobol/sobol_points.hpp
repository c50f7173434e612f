// design = "sobol": scrambled Sobol' points (Joe-Kuo direction numbers,
// Owen-scrambled by hashing), run k the k-th point.
#pragma once

#include <memory>

#include "sampling/run_points.hpp"

namespace treedyn::designs {

// Throws std::invalid_argument beyond Boost's tables or 2^32 - 1 points.
std::unique_ptr<sampling::RunPoints> sobol_points(const sampling::PointsSpec& spec);

}  // namespace treedyn::designs
