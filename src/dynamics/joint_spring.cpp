#include "dynamics/joint_spring.hpp"

namespace treedyn {

JointLoad joint_spring_load(const JointSpring& spring, const Mat3& A_parent, const Mat3& A_child,
                            const Vec3& w_parent, const Vec3& w_child) {
  // Deviation D = R_ref^T R_rel, R_rel = A_p^T A_c; D' = D [w_rel]x with
  // w_rel = A_c^T (w_c - w_p) in the child's frame.
  const Mat3 relative = A_parent.transpose() * A_child;
  const Quat deviation = spring.reference.conjugate() * Quat(relative);
  const double q0 = deviation.w();
  const Vec3 e = deviation.vec();
  const Vec3 Ke = spring.stiffness * e;
  // V = 2 e^T K e; with e' = (q0 w_rel + e x w_rel) / 2, dV/dt = -tau . w_rel for
  // tau = -2 (q0 K e + (K e) x e). Both terms are even in q, so the law is smooth.
  Vec3 tau = -2.0 * (q0 * Ke + Ke.cross(e));
  const Vec3 w_rel = A_child.transpose() * (w_child - w_parent);
  tau -= spring.damping * w_rel;
  return {A_child * tau, 2.0 * e.dot(Ke)};
}

}  // namespace treedyn
