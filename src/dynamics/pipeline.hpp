// The staged forward-dynamics pipeline: positions, velocities, forces,
// accelerations. Each stage reads what the earlier ones wrote into Data.
// Indices are in the regular order of the Model; sections are those of
// docs/wittenburg.md.
#pragma once

#include "dynamics/data.hpp"
#include "model/model.hpp"

namespace treedyn {

// Force stage of body i: gravity and point forces F_i, moments M_i, its joint's
// spring-damper moment Y_i and energy. Needs the rotations and velocities of
// i and of its parent.
void compute_body_loads(const Model& model, Data& data, int i);

// --- Recursive solver (data.solver == recursive), section 8. ---

// Position, velocity and force stages in one pass over the bodies, parents
// first: base kinematics at data.time; per body c_i, the rotated inertia
// about its inboard joint, the gyroscopic and centripetal terms, its joint's
// coupling to its parent and its loads; clears the children's sums.
void compute_articulated_kinematics(const Model& model, Data& data);

// Leaves to root: H_i factored, the articulated mass Phi_i and bias phi_i of
// every subtree. False if an H_i is not positive definite (non-finite state).
bool sweep_articulated_inertias(const Model& model, Data& data);

// Root to leaves: joint accelerations a_i, w' into data.angular_acceleration
// and the joint reactions X_i of (12) into data.articulated.joint_reaction.
void propagate_accelerations(const Model& model, Data& data);

// --- Tree-sparse L^T D L solver (data.solver == sparse_ldlt), section 4. ---

// Force stage: base kinematics at data.time, compute_body_loads for every
// body, and the subtree sums of F.
void compute_applied_loads(const Model& model, Data& data);

// Position stage: rotates K_i, b_i0, c_ii and the branch d-vectors into the
// inertial frame using data.rotation.
void compute_frame_vectors(const Model& model, Data& data);

// Velocity stage: the centripetal sums of (55) from data.angular_velocity.
void compute_velocity_terms(const Model& model, Data& data);

// Acceleration stage, part 1: the right-hand side Q of (59) with Mstar of (55).
void compute_generalised_forces(const Model& model, Data& data);

// Acceleration stage, part 2: assembles K (section 4) into its tree-sparse
// blocks and factors it as L^T D L. False if a pivot block is not positive
// definite (only with a non-finite state).
bool factor_mass_matrix(const Model& model, Data& data);

// Acceleration stage, part 3: w' = K^-1 Q into data.angular_acceleration.
void solve_angular_accelerations(const Model& model, Data& data);

// All stages of data.solver. The caller sets data.time, data.rotation and
// data.angular_velocity first. False on a numerical failure.
bool forward_dynamics(const Model& model, Data& data);

// The stages before the accelerations (positions, the base's motion, the
// loads): what recover() needs without kRecoverAccelerations, at a fraction
// of forward_dynamics' cost. Same caller's duties.
void compute_kinematics_and_loads(const Model& model, Data& data);

// K as a dense 3n x 3n matrix (regular order), for tests and diagnostics.
// Needs the L^T D L position stage (a Data made for sparse_ldlt).
Eigen::MatrixXd dense_mass_matrix(const Model& model, const Data& data);

}  // namespace treedyn
