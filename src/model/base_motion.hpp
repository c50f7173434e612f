// Prescribed translation r0(t) of the base point (body 0's attachment point).
#pragma once

#include <array>
#include <complex>
#include <memory>
#include <variant>
#include <vector>

#include "common/linalg.hpp"
#include "model/sea_state.hpp"

namespace treedyn {

// r0, r0', r0'' at one instant.
struct BaseKinematics {
  Vec3 position = Vec3::Zero();
  Vec3 velocity = Vec3::Zero();
  Vec3 acceleration = Vec3::Zero();
};

// The base point stays at `position`.
struct FixedBase {
  Vec3 position = Vec3::Zero();
};

// r0(t) = position + velocity t + acceleration t^2 / 2.
struct ConstantAccelerationBase {
  Vec3 position = Vec3::Zero();
  Vec3 velocity = Vec3::Zero();
  Vec3 acceleration = Vec3::Zero();
};

// One term amplitude * sin(2 pi frequency t + phase) along a fixed axis.
struct Harmonic {
  double amplitude = 0.0;  // m
  double frequency = 0.0;  // Hz
  double phase = 0.0;      // rad
};

// r0(t) = offset + sum over each axis of its harmonics.
struct HarmonicBase {
  Vec3 offset = Vec3::Zero();
  std::array<std::vector<Harmonic>, 3> axes;
};

// Tabulated positions, interpolated by a natural cubic spline per axis (C2:
// position, velocity and acceleration continuous). Natural end conditions make
// r0'' vanish at both ends, so outside the table the motion continues linearly
// (constant velocity) and stays C2.
struct TabulatedBase {
  std::vector<double> times;    // strictly increasing, at least 2
  std::vector<Vec3> positions;  // one per time
};

// A sea state (model/sea_state.hpp) is compiled into its components'
// complex amplitudes (BaseMotion::SeaMotion).
using BaseMotionSpec = std::variant<FixedBase, ConstantAccelerationBase, HarmonicBase, TabulatedBase, SeaStateBase>;

// A validated base motion, cheap to evaluate (spline coefficients precomputed)
// and cheap to copy (a table and its spline are shared between copies).
class BaseMotion {
 public:
  BaseMotion() = default;
  explicit BaseMotion(BaseMotionSpec spec);  // throws ModelError when invalid

  BaseKinematics at(double t) const;
  // True when r0' = r0'' = 0 for all t (energy of the tree is then conserved).
  bool is_fixed() const;

 private:
  struct Spline {
    TabulatedBase table;
    std::vector<Vec3> moments;  // second derivatives at the knots
  };
  // A sea state's components on each axis, equally spaced in frequency:
  // sum_k Im(c_k e^{i (w0 + k dw) t}) with c_k = a_k e^{i phi_k}. One sincos
  // per axis and a complex product per component (e^{i k dw t} by
  // recurrence), not a sincos per component.
  struct EquispacedHarmonics {
    double w0 = 0.0, dw = 0.0;  // rad/s
    std::vector<std::complex<double>> c;
  };
  struct SeaMotion {
    Vec3 offset = Vec3::Zero();
    std::array<EquispacedHarmonics, 3> axes;
  };
  static SeaMotion compile(const SeaStateBase& sea);
  static BaseKinematics kinematics(const FixedBase& b, double t);
  static BaseKinematics kinematics(const ConstantAccelerationBase& b, double t);
  static BaseKinematics kinematics(const HarmonicBase& b, double t);
  static BaseKinematics kinematics(const SeaMotion& b, double t);
  static BaseKinematics kinematics(const std::shared_ptr<const Spline>& b, double t);
  std::variant<FixedBase, ConstantAccelerationBase, HarmonicBase, SeaMotion, std::shared_ptr<const Spline>> motion_ =
      FixedBase{};
};

}  // namespace treedyn
