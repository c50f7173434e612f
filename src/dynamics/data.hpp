// Per-thread workspace for one tree: everything that changes with the state.
// Sized once on construction; the dynamics stages never allocate.
#pragma once

#include <vector>

#include "common/linalg.hpp"
#include "dynamics/acceleration_solver.hpp"
#include "dynamics/articulated_bodies.hpp"
#include "dynamics/mass_matrix.hpp"
#include "model/base_motion.hpp"
#include "model/model.hpp"

namespace treedyn {

struct Data {
  // Allocates the workspace of the chosen acceleration stage only (the L^T D L
  // blocks of a long chain are large; the recursion needs O(n)).
  explicit Data(const Model& model, AccelerationSolver solver = AccelerationSolver::automatic);

  AccelerationSolver solver;  // resolved: recursive or sparse_ldlt

  // Input state (regular order): A_i (body -> inertial) and inertial w_i.
  std::vector<Mat3> rotation;
  std::vector<Vec3> angular_velocity;
  double time = 0.0;

  // Position stage, both solvers.
  std::vector<Vec3> com_to_inboard_joint;  // c_i = c_ii^0 = d_ii^0

  // Position and velocity stages of the L^T D L solver only: section 3
  // constants rotated into the inertial frame, and the centripetal sums of (55).
  std::vector<Mat3> augmented_inertia;       // K_i^0 = A_i K_i A_i^T
  std::vector<Vec3> barycentre_to_inboard;   // b_i0^0
  std::vector<Vec3> branch_d;                // d_{p(k) j}^0, j in sub(k), rotated by A_p(k)
  std::vector<Vec3> centripetal_b;           // w_j x (w_j x b_j0)
  std::vector<Vec3> subtree_centripetal_b;   // its sum over sub(k)
  std::vector<Vec3> ancestor_centripetal_d;  // sum over j < i of w_j x (w_j x d_ji)

  // Force stage.
  BaseKinematics base;
  std::vector<Vec3> force;            // F_i through the CoM (gravity + point forces)
  std::vector<Vec3> subtree_force;    // sum of F over sub(i)
  std::vector<Vec3> moment;           // M_i about the CoM (applied + point-force moments)
  std::vector<Vec3> joint_moment;     // Y_a on body a (reversed on p(a))
  std::vector<double> spring_energy;  // per joint

  // Acceleration stage, L^T D L: K w' = Q (empty with the recursive solver).
  Eigen::VectorXd generalised_force;  // Q_i = Mstar_i + M_i + Y_i - sum Y_k (59)
  SparseMassMatrix mass_matrix;       // K, then its L^T D L factors

  // Acceleration stage, recursive: section 8 (empty with L^T D L).
  ArticulatedBodies articulated;

  // Result of either.
  Eigen::VectorXd angular_acceleration;  // w' (3n), regular order
};

}  // namespace treedyn
