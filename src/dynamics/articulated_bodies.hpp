// Workspace of the recursive acceleration stage (docs/wittenburg.md, section 8):
// per body the kinematic couplings to its parent, the sums its children
// contribute, and the factors that the root-to-leaves sweep reuses. All
// vectors and matrices are inertial. Sized once; the sweeps never allocate.
#pragma once

#include <vector>

#include "common/cholesky3.hpp"
#include "common/linalg.hpp"

namespace treedyn {

struct ArticulatedBodies {
  ArticulatedBodies() = default;
  explicit ArticulatedBodies(int n);

  // Position and velocity stage.
  std::vector<Vec3> centripetal_c;        // kappa_i = w_i x (w_i x c_i)
  std::vector<Vec3> gyroscopic;           // w_i x (J_i^0 w_i)
  std::vector<Mat3> inertia_about_joint;  // A_i (J_i - m_i [c_ii]x^2) A_i^T = J_i^0 - m_i [c_i]x^2
  std::vector<Vec3> coupling_arm;         // g_i = c_p - e_i, G_i = [g_i]x (p = p(i); 0 on the base)
  std::vector<Vec3> joint_bias;           // zeta_i - kappa_p: a_i = a_p + G_i w_p' + joint_bias_i

  // Children's contributions, summed in the leaves-to-root sweep.
  std::vector<Mat3> child_h;      // -sum_k G_k Phi_k G_k
  std::vector<Mat3> child_b;      // sum_k G_k Phi_k
  std::vector<Vec3> child_beta;   // sum_k (G_k f_k - Y_k)
  std::vector<Mat3> child_p;      // sum_k Phi_k
  std::vector<Vec3> child_gamma;  // sum_k f_k

  // Factors: H_i = L L^T, Y = L^-1 B_i, y = L^-1 beta_i; articulated mass.
  std::vector<Cholesky3> h_factor;
  std::vector<Mat3> scaled_b;          // L^-1 B_i
  std::vector<Vec3> scaled_beta;       // L^-1 beta_i
  std::vector<Mat3> articulated_mass;  // Phi_i
  std::vector<Vec3> articulated_bias;  // phi_i

  // Root-to-leaves results.
  std::vector<Vec3> joint_acceleration;  // a_i: linear acceleration of joint i's point
  std::vector<Vec3> joint_reaction;      // X_i = Phi_i a_i + phi_i (12), on body i
};

}  // namespace treedyn
