// The state a trajectory starts from: every body's orientation and absolute
// angular velocity, in the user's body order. With a parameter vector it is
// all that makes one ensemble sample.
#pragma once

#include <optional>
#include <vector>

#include "common/linalg.hpp"

namespace treedyn {

struct InitialState {
  std::vector<Mat3> rotation;          // A_i, body -> inertial
  std::vector<Vec3> angular_velocity;  // w_i, inertial components
  // Per body, the angular velocity's body-frame components when the job gave
  // them so: the spin then turns with the body if its orientation changes.
  // Empty, or one entry per body.
  std::vector<std::optional<Vec3>> body_frame_spin;
};

// After perturbations changed some orientations of `state` (a copy of
// `nominal`): each spin given in a body's frame is re-expressed with that
// body's new orientation, by the reader's own expression A w_body, so an
// unchanged orientation keeps its angular velocity bit for bit.
void turn_body_frame_spins(const InitialState& nominal, InitialState& state);

}  // namespace treedyn
