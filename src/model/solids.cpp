#include "model/solids.hpp"

#include <numbers>

namespace treedyn {

Vec3 box_principal_moments(double m, const Vec3& s) {
  const Vec3 sq = s.cwiseProduct(s);
  return m / 12.0 * Vec3(sq.y() + sq.z(), sq.x() + sq.z(), sq.x() + sq.y());
}

double cylinder_volume(double r, double l) { return std::numbers::pi * r * r * l; }

Vec3 cylinder_principal_moments(double m, double r, double l) {
  const double transverse = m * (3.0 * r * r + l * l) / 12.0;
  return Vec3(transverse, transverse, 0.5 * m * r * r);
}

double sphere_volume(double r) { return 4.0 / 3.0 * std::numbers::pi * r * r * r; }

Vec3 sphere_principal_moments(double m, double r) { return Vec3::Constant(0.4 * m * r * r); }

}  // namespace treedyn
