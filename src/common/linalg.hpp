// Fixed-size linear-algebra vocabulary shared by every module.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace treedyn {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

// [v]x: the cross-product matrix, [v]x u = v x u.
inline Mat3 cross_matrix(const Vec3& v) {
  Mat3 m;
  m << 0.0, -v.z(), v.y(),  //
      v.z(), 0.0, -v.x(),   //
      -v.y(), v.x(), 0.0;
  return m;
}

// Dyadic block ((b . d) E - b d^T): the matrix of w -> d x (w x b).
inline Mat3 cross_cross_matrix(const Vec3& d, const Vec3& b) { return b.dot(d) * Mat3::Identity() - b * d.transpose(); }

// The unit quaternion of rotation A: of q and -q, the one with q0 >= 0 (the
// sign rule of every output).
inline Quat canonical_quaternion(const Mat3& A) {
  Quat q(A);
  if (q.w() < 0.0) q.coeffs() *= -1.0;
  return q;
}

}  // namespace treedyn
