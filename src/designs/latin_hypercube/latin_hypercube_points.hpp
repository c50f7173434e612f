// design = "latin_hypercube": every dimension split into N strata, each hit
// exactly once: run k's stratum in dimension d is a keyed permutation
// pi_d(k) of the N runs, and its place inside the stratum a uniform.
#pragma once

#include <memory>

#include "sampling/run_points.hpp"

namespace treedyn::designs {

std::unique_ptr<sampling::RunPoints> latin_hypercube_points(const sampling::PointsSpec& spec);

}  // namespace treedyn::designs
