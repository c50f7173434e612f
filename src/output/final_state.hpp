// The state at the last output time as one row: per body (user order) the
// orientation quaternion q0..q3 (q0 >= 0) and the inertial angular velocity.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "dynamics/recovered.hpp"
#include "model/topology.hpp"

namespace treedyn {

inline constexpr std::size_t kFinalStatePerBody = 7;

// "rod.q0", ..., "rod.wz", per body in the user's order.
std::vector<std::string> final_state_columns(const Topology& tree);
// Writes kFinalStatePerBody numbers per body into `row`.
void write_final_state(const Recovered& state, std::span<double> row);

}  // namespace treedyn
