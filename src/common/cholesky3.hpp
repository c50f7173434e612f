// Cholesky factorisation H = L L^T of a symmetric positive-definite 3x3 matrix
// and its triangular solves, written out for 3x3. Eigen's LLT<Matrix3d> reaches
// general-size triangular-solve routines (BENCHMARKS.md, "Profile, before and
// after"); these are straight-line code on the six entries of L, with the
// reciprocals of its diagonal stored so that a solve has no division.
#pragma once

#include <cmath>

#include "common/linalg.hpp"

namespace treedyn {

struct Cholesky3 {
  // Lower triangle of L, row by row; inv_lXX = 1 / lXX.
  double l00 = 1.0, l10 = 0.0, l11 = 1.0, l20 = 0.0, l21 = 0.0, l22 = 1.0;
  double inv_l00 = 1.0, inv_l11 = 1.0, inv_l22 = 1.0;
};

// Reads the lower triangle of H only. False when H is not positive definite
// (or not finite); `out` is then unusable.
inline bool factor_cholesky3(const Mat3& H, Cholesky3& out) {
  const double d0 = H(0, 0);
  if (!(d0 > 0.0)) return false;
  out.l00 = std::sqrt(d0);
  out.inv_l00 = 1.0 / out.l00;
  out.l10 = H(1, 0) * out.inv_l00;
  out.l20 = H(2, 0) * out.inv_l00;
  const double d1 = H(1, 1) - out.l10 * out.l10;
  if (!(d1 > 0.0)) return false;
  out.l11 = std::sqrt(d1);
  out.inv_l11 = 1.0 / out.l11;
  out.l21 = (H(2, 1) - out.l20 * out.l10) * out.inv_l11;
  const double d2 = H(2, 2) - out.l20 * out.l20 - out.l21 * out.l21;
  if (!(d2 > 0.0)) return false;
  out.l22 = std::sqrt(d2);
  out.inv_l22 = 1.0 / out.l22;
  return true;
}

// L^-1 v (forward substitution).
inline Vec3 solve_lower(const Cholesky3& c, const Vec3& v) {
  const double x0 = v.x() * c.inv_l00;
  const double x1 = (v.y() - c.l10 * x0) * c.inv_l11;
  const double x2 = (v.z() - c.l20 * x0 - c.l21 * x1) * c.inv_l22;
  return {x0, x1, x2};
}

// L^-T v (back substitution).
inline Vec3 solve_upper(const Cholesky3& c, const Vec3& v) {
  const double x2 = v.z() * c.inv_l22;
  const double x1 = (v.y() - c.l21 * x2) * c.inv_l11;
  const double x0 = (v.x() - c.l10 * x1 - c.l20 * x2) * c.inv_l00;
  return {x0, x1, x2};
}

// L^-1 M, column by column.
inline Mat3 solve_lower(const Cholesky3& c, const Mat3& m) {
  Mat3 out;
  for (int j = 0; j < 3; ++j) out.col(j) = solve_lower(c, Vec3(m.col(j)));
  return out;
}

// H^-1 v = L^-T L^-1 v.
inline Vec3 solve_cholesky3(const Cholesky3& c, const Vec3& v) { return solve_upper(c, solve_lower(c, v)); }

}  // namespace treedyn
