// Central inertia tensors of homogeneous solids, in their own principal frame.
#pragma once

#include "common/linalg.hpp"

namespace treedyn {

inline double box_volume(const Vec3& size) { return size.x() * size.y() * size.z(); }
Vec3 box_principal_moments(double mass, const Vec3& size);  // edges along x, y, z
double cylinder_volume(double radius, double length);
Vec3 cylinder_principal_moments(double mass, double radius, double length);  // axis along z
double sphere_volume(double radius);
Vec3 sphere_principal_moments(double mass, double radius);

}  // namespace treedyn
