// The four orientation parameterisations of docs/wittenburg.md, section 5,
// and their charts.
//
// A body's orientation is A = C * R(q): q are the integrated coordinates and C
// a constant "chart base" rotation. For quaternions and direction cosines C is
// the identity; for the angle sets C is re-chosen when the angles approach
// their singular set (see recentre), so the same physical motion continues in
// a chart where the angles are far from singular.
#pragma once

#include <string_view>

#include "common/enum_names.hpp"
#include "common/linalg.hpp"

namespace treedyn {

enum class Parameterisation {
  euler313,           // Euler angles psi, theta, phi: A = Rz(psi) Rx(theta) Rz(phi)
  bryant123,          // Bryant angles a1, a2, a3: A = Rx(a1) Ry(a2) Rz(a3)
  quaternion,         // Euler parameters q0..q3, scalar first
  direction_cosines,  // the 9 entries of A, row-major
};

int coordinate_count(Parameterisation p);
inline constexpr NameTable<Parameterisation, 4> kParameterisationNames{
    {{Parameterisation::quaternion, "quaternion"},
     {Parameterisation::euler313, "euler313"},
     {Parameterisation::bryant123, "bryant123"},
     {Parameterisation::direction_cosines, "direction_cosines"}}};
inline std::string_view name(Parameterisation p) { return name_in(kParameterisationNames, p); }
inline bool parse_parameterisation(std::string_view text, Parameterisation& out) {
  return parse_in(kParameterisationNames, text, out);
}

// R(q): the rotation the coordinates describe (body -> inertial, before the
// chart base). Quaternions are normalised and direction cosines
// re-orthonormalised here, so small drift of the integrated coordinates never
// reaches the dynamics.
Mat3 rotation_from_coordinates(Parameterisation p, const double* q);

// q' from q and the body-frame angular velocity w^(i) = A^T w (64)-(68).
// The chart base is constant, so these are the textbook equations.
void coordinate_rates(Parameterisation p, const double* q, const Vec3& w_body, double* q_dot);

// How far q is from needing a new chart: positive while the chart is good,
// crossing zero (downwards) when the integrator must stop and recentre. For
// angle sets this is the distance from the singular set (|cos a2| for Bryant,
// |sin theta| for Euler, minus a threshold); for quaternions and direction
// cosines it is the allowed drift of the norm / orthonormality minus the drift.
double chart_margin(Parameterisation p, const double* q);

// Re-expresses orientation A in a fresh chart: overwrites the coordinates q
// (on entry: the current ones) with coordinates far from any singularity (or
// exactly normalised, keeping a quaternion's sign) and returns the chart base
// C with A = C R(q).
Mat3 recentre(Parameterisation p, const Mat3& A, double* q);

}  // namespace treedyn
