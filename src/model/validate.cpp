#include "model/validate.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <sstream>

#include "common/error.hpp"

namespace treedyn {
namespace {

std::string format(const Vec3& v) {
  std::ostringstream s;
  s << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return s.str();
}

bool is_symmetric(const Mat3& m) {
  const double scale = std::max(m.cwiseAbs().maxCoeff(), 1e-300);
  return (m - m.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * scale;
}

}  // namespace

void require_finite(const std::string& who, const std::string& field, const Vec3& v) {
  if (!v.allFinite()) throw ModelError(who + ": " + field + " " + format(v) + " must be finite (no NaN or infinity)");
}

void require_positive_mass(const std::string& who, double mass) {
  if (!std::isfinite(mass) || !(mass > 0.0)) {
    std::ostringstream s;
    s << who << ": mass " << mass << " kg is not allowed; mass must be positive and finite";
    throw ModelError(s.str());
  }
}

void require_positive(const std::string& who, const std::string& field, const std::string& unit, double value) {
  if (!std::isfinite(value) || !(value > 0.0)) {
    std::ostringstream s;
    s << who << ": " << field << " " << value << (unit == "1" ? "" : " " + unit)
      << " is not allowed; it must be positive and finite";
    throw ModelError(s.str());
  }
}

void require_valid_inertia(const std::string& who, const Mat3& inertia) {
  if (!inertia.allFinite()) throw ModelError(who + ": inertia has a NaN or infinite entry; all entries must be finite");
  if (!is_symmetric(inertia)) throw ModelError(who + ": inertia tensor is not symmetric; it must equal its transpose");
  const Vec3 moments = Eigen::SelfAdjointEigenSolver<Mat3>(inertia, Eigen::EigenvaluesOnly).eigenvalues();  // ascending
  if (!(moments[0] > 0.0)) {
    std::ostringstream s;
    s << who << ": inertia tensor is not positive definite (principal moments " << format(moments)
      << "); every principal moment must be > 0";
    throw ModelError(s.str());
  }
  if (moments[2] > (moments[0] + moments[1]) * (1.0 + 1e-9)) {
    std::ostringstream s;
    s << who << ": principal moments " << format(moments)
      << " violate the triangle inequality; each must be at most the sum of the other two";
    throw ModelError(s.str());
  }
}

void require_psd(const std::string& who, const std::string& field, const Mat3& m) {
  if (!m.allFinite()) throw ModelError(who + ": " + field + " has a NaN or infinite entry; all entries must be finite");
  if (!is_symmetric(m)) throw ModelError(who + ": " + field + " is not symmetric; it must equal its transpose");
  const Vec3 ev = Eigen::SelfAdjointEigenSolver<Mat3>(m, Eigen::EigenvaluesOnly).eigenvalues();
  if (ev[0] < -1e-12 * std::max(1.0, ev[2])) {
    std::ostringstream s;
    s << who << ": " << field << " has a negative eigenvalue " << ev[0] << "; it must be positive semi-definite";
    throw ModelError(s.str());
  }
}

}  // namespace treedyn
