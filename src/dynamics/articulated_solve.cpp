// Acceleration stage, recursive (docs/wittenburg.md, section 8): w' from one 3x3
// articulated mass per body, leaves to root, then the joint accelerations and
// w' root to leaves. No K is formed; O(n) for any tree. Every vector is
// inertial; children have larger indices than their parents.
#include "dynamics/pipeline.hpp"

namespace treedyn {

ArticulatedBodies::ArticulatedBodies(int bodies) {
  const auto n = static_cast<std::size_t>(bodies);
  for (auto* v : {&centripetal_c, &gyroscopic, &coupling_arm, &joint_bias, &child_beta, &child_gamma, &scaled_beta,
                  &articulated_bias, &joint_acceleration, &joint_reaction})
    v->assign(n, Vec3::Zero());
  for (auto* m : {&inertia_about_joint, &child_h, &child_b, &child_p, &scaled_b, &articulated_mass})
    m->assign(n, Mat3::Zero());
  h_factor.assign(n, Cholesky3{});
}

namespace {

// A S A^T for a symmetric S, formed as a symmetric matrix (lower triangle
// computed, then mirrored) so that H stays exactly symmetric.
Mat3 rotate_symmetric(const Mat3& A, const Mat3& S) {
  const Mat3 AS = A * S;
  Mat3 out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c <= r; ++c) out(r, c) = out(c, r) = AS.row(r).dot(A.row(c));
  return out;
}

// P - Y^T Y (symmetric by construction).
Mat3 minus_gram(const Mat3& P, const Mat3& Y) {
  Mat3 out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c <= r; ++c) out(r, c) = out(c, r) = P(r, c) - Y.col(r).dot(Y.col(c));
  return out;
}

}  // namespace

void compute_articulated_kinematics(const Model& model, Data& data) {
  ArticulatedBodies& ab = data.articulated;
  const Topology& tree = model.tree();
  data.base = model.base_motion.at(data.time);
  for (int i = 0; i < model.n; ++i) {
    const Mat3& A = data.rotation[i];
    const Vec3& w = data.angular_velocity[i];
    const Vec3 c = A * model.com_to_inboard_joint[i];  // c_i
    data.com_to_inboard_joint[i] = c;
    const Vec3 w_x_c = w.cross(c);
    ab.centripetal_c[i] = w.cross(w_x_c);
    // One rotated inertia: about the joint, H_own = J_i^0 - m [c]x^2 (from a
    // body-frame constant). The central J_i^0 w = H_own w + m c x (c x w)
    // = H_own w - m c x (w x c) needs no second rotation.
    const Mat3 H_own = rotate_symmetric(A, model.inertia_about_joint[i]);
    ab.inertia_about_joint[i] = H_own;
    ab.gyroscopic[i] = w.cross(H_own * w - model.mass[i] * c.cross(w_x_c));
    const int p = tree.parent[i];
    if (p == kBase) {
      ab.coupling_arm[i].setZero();
      ab.joint_bias[i].setZero();
    } else {
      const Vec3 e = data.rotation[p] * model.parent_com_to_joint[i];  // e_i on the parent
      const Vec3& wp = data.angular_velocity[p];
      ab.coupling_arm[i] = data.com_to_inboard_joint[p] - e;           // g_i: G_i = [c_p - e_i]x
      ab.joint_bias[i] = wp.cross(wp.cross(e)) - ab.centripetal_c[p];  // zeta_i - kappa_p
    }
    compute_body_loads(model, data, i);
    ab.child_h[i].setZero();
    ab.child_b[i].setZero();
    ab.child_beta[i].setZero();
    ab.child_p[i].setZero();
    ab.child_gamma[i].setZero();
  }
}

bool sweep_articulated_inertias(const Model& model, Data& data) {
  ArticulatedBodies& ab = data.articulated;
  const Topology& tree = model.tree();
  for (int i = model.n - 1; i >= 0; --i) {
    const double m = model.mass[i];
    const Vec3& c = data.com_to_inboard_joint[i];
    const Vec3& kappa = ab.centripetal_c[i];
    const Vec3& F = data.force[i];
    // Euler about the CoM with the kinematics substituted: H w' = B a + beta.
    const Mat3 H = ab.inertia_about_joint[i] + ab.child_h[i];  // J^0 - m [c]x^2 - sum G Phi G
    Mat3 B = ab.child_b[i];                                    // m [c]x + sum G Phi
    B(0, 1) -= m * c.z();
    B(0, 2) += m * c.y();
    B(1, 0) += m * c.z();
    B(1, 2) -= m * c.x();
    B(2, 0) -= m * c.y();
    B(2, 1) += m * c.x();
    const Vec3 beta =
        -ab.gyroscopic[i] - c.cross(m * kappa + F) + data.moment[i] + data.joint_moment[i] + ab.child_beta[i];
    Cholesky3& L = ab.h_factor[i];
    if (!factor_cholesky3(H, L)) return false;
    ab.scaled_b[i] = solve_lower(L, B);
    ab.scaled_beta[i] = solve_lower(L, beta);
    // Newton with w' eliminated: X = Phi a + phi (a Schur complement).
    Mat3 P = ab.child_p[i];
    P.diagonal().array() += m;
    ab.articulated_mass[i] = minus_gram(P, ab.scaled_b[i]);
    ab.articulated_bias[i] = -m * kappa - F + ab.child_gamma[i] - ab.scaled_b[i].transpose() * ab.scaled_beta[i];

    const int p = tree.parent[i];
    if (p == kBase) continue;
    // What subtree i adds to its parent's equations through X_i at e_i.
    const Vec3& g = ab.coupling_arm[i];
    const Mat3& Phi = ab.articulated_mass[i];
    const Vec3 f = Phi * ab.joint_bias[i] + ab.articulated_bias[i];
    Mat3 GPhi;  // [g]x Phi
    for (int col = 0; col < 3; ++col) GPhi.col(col) = g.cross(Phi.col(col));
    // -G Phi G = -(G Phi) G; row r of (G Phi) G is -(g x row r of G Phi).
    for (int r = 0; r < 3; ++r) ab.child_h[p].row(r) += g.cross(Vec3(GPhi.row(r))).transpose();
    ab.child_b[p] += GPhi;
    ab.child_beta[p] += g.cross(f) - data.joint_moment[i];
    ab.child_p[p] += Phi;
    ab.child_gamma[p] += f;
  }
  return true;
}

void propagate_accelerations(const Model& model, Data& data) {
  ArticulatedBodies& ab = data.articulated;
  const Topology& tree = model.tree();
  for (int i = 0; i < model.n; ++i) {
    const int p = tree.parent[i];
    Vec3 a;  // a_i
    if (p == kBase) {
      a = data.base.acceleration;  // r0''
    } else {
      const Vec3 wp_dot = data.angular_acceleration.segment<3>(3 * p);
      a = ab.joint_acceleration[p] + ab.coupling_arm[i].cross(wp_dot) + ab.joint_bias[i];
    }
    ab.joint_acceleration[i] = a;
    // w' = H^-1 (B a + beta) = L^-T (L^-1 B a + L^-1 beta).
    data.angular_acceleration.segment<3>(3 * i) = solve_upper(ab.h_factor[i], ab.scaled_b[i] * a + ab.scaled_beta[i]);
    ab.joint_reaction[i] = ab.articulated_mass[i] * a + ab.articulated_bias[i];
  }
}

}  // namespace treedyn
