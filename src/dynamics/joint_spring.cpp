#include "dynamics/joint_spring.hpp"

#include <cmath>

namespace treedyn {
namespace {

struct SpringMoment {
  Vec3 moment;  // on the child, child frame
  double energy;
};

// V = 2 e^T K e, e the vector part of the deviation's quaternion. With
// e' = (q0 w + e x w) / 2, dV/dt = -tau . w for tau = -2 (q0 K e + (K e) x e).
// Both terms are even in q, so the law is smooth.
SpringMoment quaternion_law(const Mat3& K, const Quat& deviation) {
  const double q0 = deviation.w();
  const Vec3 e = deviation.vec();
  const Vec3 Ke = K * e;
  return {-2.0 * (q0 * Ke + Ke.cross(e)), 2.0 * e.dot(Ke)};
}

// V = theta^T K theta / 2, theta the rotation vector of the deviation (angle
// in [0, pi]). theta' = Jr^-1(theta) w with the right Jacobian's inverse
// Jr^-1 = E + [theta]x / 2 + c [theta]x^2, so dV/dt = -tau . w for
// tau = -Jr^-T K theta = -(K theta - theta x K theta / 2 + c theta x (theta x K theta)),
// which is -K theta when K theta is parallel to theta (K = k E).
// c = 1/angle^2 - cot(angle/2) / (2 angle); cot(angle/2) = q0 / |e|.
SpringMoment rotation_vector_law(const Mat3& K, Quat deviation) {
  if (deviation.w() < 0.0) deviation.coeffs() *= -1.0;  // the rotation by an angle in [0, pi]
  const double q0 = deviation.w();
  const Vec3 e = deviation.vec();
  const double s = e.norm();  // sin(angle / 2)
  const double angle = 2.0 * std::atan2(s, q0);
  const Vec3 theta = s > 0.0 ? Vec3(e * (angle / s)) : Vec3::Zero();
  const double a2 = angle * angle;
  // Series below 1e-3 rad, where the closed form loses digits to cancellation.
  const double c = angle < 1e-3 ? 1.0 / 12.0 + a2 / 720.0 + a2 * a2 / 30240.0 : 1.0 / a2 - q0 / (2.0 * angle * s);
  const Vec3 Kt = K * theta;
  const Vec3 tau = -(Kt - 0.5 * theta.cross(Kt) + c * theta.cross(theta.cross(Kt)));
  return {tau, 0.5 * theta.dot(Kt)};
}

}  // namespace

JointLoad joint_spring_load(const JointSpring& spring, const Mat3& A_parent, const Mat3& A_child, const Vec3& w_parent,
                            const Vec3& w_child) {
  // Deviation D = R_ref^T R_rel, R_rel = A_p^T A_c; D' = D [w_rel]x with
  // w_rel = A_c^T (w_c - w_p) in the child's frame.
  const Mat3 relative = A_parent.transpose() * A_child;
  const Quat deviation = spring.reference.conjugate() * Quat(relative);
  SpringMoment s = spring.law == SpringLaw::quaternion ? quaternion_law(spring.stiffness, deviation)
                                                       : rotation_vector_law(spring.stiffness, deviation);
  const Vec3 w_rel = A_child.transpose() * (w_child - w_parent);
  s.moment -= spring.damping * w_rel;
  return {A_child * s.moment, s.energy};
}

}  // namespace treedyn
