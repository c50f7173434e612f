#include "kinematics/parameterisation.hpp"

#include <cmath>
#include <numbers>

namespace treedyn {
namespace {

// Angle sets switch chart when the angles come this close to gimbal lock
// (|cos a2| or |sin theta| below it: about 76 degrees from the centre of the
// chart). The kinematic equations' gain 1/cos grows only to 4 before then.
constexpr double kAngleChartLimit = 0.25;
// Quaternion norm^2 and direction-cosine orthonormality may drift this far
// before the coordinates are re-projected (with a fresh integrator start).
// The dynamics never see the drift (rotation_from_coordinates normalises), so
// the limit only keeps the coordinates well conditioned; a loose one avoids
// restarting every few steps at loose tolerances.
constexpr double kDriftLimit = 1e-2;

Mat3 rx(double a) { return Eigen::AngleAxisd(a, Vec3::UnitX()).toRotationMatrix(); }
Mat3 ry(double a) { return Eigen::AngleAxisd(a, Vec3::UnitY()).toRotationMatrix(); }
Mat3 rz(double a) { return Eigen::AngleAxisd(a, Vec3::UnitZ()).toRotationMatrix(); }

Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> dcm(const double* q) {
  return Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(q);
}

double orthonormality_drift(const double* q) {
  const Mat3 A = dcm(q);
  return (A.transpose() * A - Mat3::Identity()).cwiseAbs().maxCoeff();
}

}  // namespace

int coordinate_count(Parameterisation p) {
  switch (p) {
    case Parameterisation::euler313:
    case Parameterisation::bryant123:
      return 3;
    case Parameterisation::quaternion:
      return 4;
    case Parameterisation::direction_cosines:
      return 9;
  }
  return 0;
}

Mat3 rotation_from_coordinates(Parameterisation p, const double* q) {
  switch (p) {
    case Parameterisation::euler313:
      return rz(q[0]) * rx(q[1]) * rz(q[2]);
    case Parameterisation::bryant123:
      return rx(q[0]) * ry(q[1]) * rz(q[2]);
    case Parameterisation::quaternion:
      return Quat(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
    case Parameterisation::direction_cosines: {
      // Newton-Schulz iteration towards the polar factor: the error squares
      // each step, so three steps take a drift of 1e-2 to ~1e-15.
      Mat3 A = dcm(q);
      for (int k = 0; k < 3; ++k) A = 0.5 * A * (3.0 * Mat3::Identity() - A.transpose() * A);
      return A;
    }
  }
  return Mat3::Identity();
}

void coordinate_rates(Parameterisation p, const double* q, const Vec3& w, double* q_dot) {
  switch (p) {
    case Parameterisation::bryant123: {  // (66)
      const double c2 = std::cos(q[1]), t2 = std::tan(q[1]);
      const double s3 = std::sin(q[2]), c3 = std::cos(q[2]);
      const double u = w.x() * c3 - w.y() * s3;
      q_dot[0] = u / c2;
      q_dot[1] = w.x() * s3 + w.y() * c3;
      q_dot[2] = w.z() - u * t2;
      return;
    }
    case Parameterisation::euler313: {  // (65)
      const double sth = std::sin(q[1]), cth = std::cos(q[1]);
      const double sph = std::sin(q[2]), cph = std::cos(q[2]);
      const double u = w.x() * sph + w.y() * cph;
      q_dot[0] = u / sth;
      q_dot[1] = w.x() * cph - w.y() * sph;
      q_dot[2] = w.z() - u * cth / sth;
      return;
    }
    case Parameterisation::quaternion: {  // (67): q' = 1/2 q (x) (0, w)
      const double q0 = q[0], q1 = q[1], q2 = q[2], q3 = q[3];
      q_dot[0] = 0.5 * (-q1 * w.x() - q2 * w.y() - q3 * w.z());
      q_dot[1] = 0.5 * (q0 * w.x() + q2 * w.z() - q3 * w.y());
      q_dot[2] = 0.5 * (q0 * w.y() + q3 * w.x() - q1 * w.z());
      q_dot[3] = 0.5 * (q0 * w.z() + q1 * w.y() - q2 * w.x());
      return;
    }
    case Parameterisation::direction_cosines: {  // (68): A' = A [w]x
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> out(q_dot);
      out = dcm(q) * cross_matrix(w);
      return;
    }
  }
}

double chart_margin(Parameterisation p, const double* q) {
  switch (p) {
    case Parameterisation::bryant123:
      return std::abs(std::cos(q[1])) - kAngleChartLimit;
    case Parameterisation::euler313:
      return std::abs(std::sin(q[1])) - kAngleChartLimit;
    case Parameterisation::quaternion:
      return kDriftLimit - std::abs(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3] - 1.0);
    case Parameterisation::direction_cosines:
      return kDriftLimit - orthonormality_drift(q);
  }
  return 1.0;
}

Mat3 recentre(Parameterisation p, const Mat3& A, double* q) {
  switch (p) {
    case Parameterisation::bryant123:  // centre of the chart: all angles zero
      q[0] = q[1] = q[2] = 0.0;
      return A;
    case Parameterisation::euler313: {  // centre: theta = 90 degrees
      q[0] = 0.0;
      q[1] = 0.5 * std::numbers::pi;
      q[2] = 0.0;
      return A * rotation_from_coordinates(p, q).transpose();
    }
    case Parameterisation::quaternion: {
      Quat u = Quat(A).normalized();
      // Keep the sign of the incoming coordinates: q and -q are one rotation.
      if (u.w() * q[0] + u.x() * q[1] + u.y() * q[2] + u.z() * q[3] < 0.0) u.coeffs() *= -1.0;
      q[0] = u.w();
      q[1] = u.x();
      q[2] = u.y();
      q[3] = u.z();
      return Mat3::Identity();
    }
    case Parameterisation::direction_cosines: {
      const Mat3 R = Quat(A).normalized().toRotationMatrix();
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> out(q);
      out = R;
      return Mat3::Identity();
    }
  }
  return Mat3::Identity();
}

}  // namespace treedyn
