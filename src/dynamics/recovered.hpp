// Quantities recovered from a state after forward_dynamics (docs/wittenburg.md,
// section 6), in the user's body order (index = position in
// ModelSpec::bodies).
#pragma once

#include <vector>

#include "common/linalg.hpp"
#include "dynamics/data.hpp"
#include "model/model.hpp"

namespace treedyn {

struct Energies {
  double kinetic = 0.0;    // T
  double potential = 0.0;  // V: gravity and the constant point forces
  double spring = 0.0;     // joint springs, each by its law (model/model_spec.hpp)
  double total() const { return kinetic + potential + spring; }
};

struct Recovered {
  double time = 0.0;
  BaseKinematics base;
  std::vector<Mat3> rotation;              // A_i
  std::vector<Vec3> angular_velocity;      // w_i, inertial
  std::vector<Vec3> angular_acceleration;  // w_i', inertial
  std::vector<Vec3> com_position;          // r_i (20)
  std::vector<Vec3> com_velocity;          // r_i'
  std::vector<Vec3> com_acceleration;      // r_i''
  std::vector<Vec3> joint_position;        // body i's inboard joint point
  std::vector<Vec3> joint_reaction;        // X_a on body a (12), a = the joint's child
  std::vector<double> joint_angle;         // relative rotation of the inboard joint, rad in [0, pi]
  std::vector<Vec3> joint_axis;            // its axis, parent frame (zero when the angle is zero)
  std::vector<Vec3> joint_moment;          // spring-damper moment Y_a on body a, inertial
  Energies energy;
  Vec3 angular_momentum_about_base = Vec3::Zero();  // about the base point r0(t)
};

// What recover() computes beyond the time, the base, the rotations, the
// angular velocities, the positions and velocities of the centres of mass
// and joint points and the joint moments (always): each part costs time at
// every output time, so a recorder asks only for what it writes.
enum RecoveredPart : unsigned {
  kRecoverAccelerations = 1u,    // w', r'', joint reactions: need forward_dynamics
  kRecoverJointAngles = 2u,      // joint_angle, joint_axis: an angle-axis per joint
  kRecoverEnergy = 4u,           // T, V, spring energy
  kRecoverAngularMomentum = 8u,  // about the base point
  kRecoverEverything = 15u,
};

// Needs forward_dynamics(model, data) on the current state, or only
// compute_kinematics_and_loads (dynamics/pipeline.hpp) when `parts` leaves
// out kRecoverAccelerations. Parts left out keep what an earlier call left
// there (zero at first).
Recovered recover(const Model& model, const Data& data);
// The same into `out`, reusing its storage (no allocation after the first
// call with a given model): for code that recovers at every output time.
void recover(const Model& model, const Data& data, Recovered& out, unsigned parts = kRecoverEverything);

// Position of a point fixed in a body (from its CoM, body frame).
Vec3 body_point_position(const Recovered& r, int user_body, const Vec3& point);

}  // namespace treedyn
