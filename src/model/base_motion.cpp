#include "model/base_motion.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "common/error.hpp"
#include "model/model_spec.hpp"

namespace treedyn {
namespace {

bool finite(const Vec3& v) { return v.allFinite(); }

void validate(const FixedBase& b) {
  if (!finite(b.position)) throw ModelError("base motion 'fixed': position must be finite", kBaseName);
}

void validate(const ConstantAccelerationBase& b) {
  if (!finite(b.position) || !finite(b.velocity) || !finite(b.acceleration))
    throw ModelError(
        "base motion 'constant_acceleration': position, velocity and acceleration must be finite", kBaseName);
}

void validate(const HarmonicBase& b) {
  if (!finite(b.offset)) throw ModelError("base motion 'harmonic': offset must be finite", kBaseName);
  static const char* axis_name[3] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    for (std::size_t k = 0; k < b.axes[axis].size(); ++k) {
      const Harmonic& h = b.axes[axis][k];
      const std::string where = std::string("base motion 'harmonic', axis ") + axis_name[axis] +
                                " term " + std::to_string(k + 1) + ": ";
      if (!std::isfinite(h.amplitude) || !std::isfinite(h.phase))
        throw ModelError(where + "amplitude and phase must be finite", kBaseName);
      if (!std::isfinite(h.frequency) || h.frequency < 0.0)
        throw ModelError(where + "frequency must be finite and >= 0 Hz", kBaseName);
    }
  }
}

void validate(const SeaStateBase& b) {
  if (!finite(b.offset)) throw ModelError("base motion 'sea_state': offset must be finite", kBaseName);
  static const char* axis_name[3] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis)
    if (b.axes[axis]) validate_sea_state(*b.axes[axis], axis_name[axis]);
}

// The sea state's harmonic sum: its components along each axis.
HarmonicBase compile(const SeaStateBase& b) {
  HarmonicBase h;
  h.offset = b.offset;
  for (int axis = 0; axis < 3; ++axis)
    if (b.axes[axis])
      for (const SeaComponent& c : components(*b.axes[axis]))
        h.axes[axis].push_back({c.amplitude, c.frequency, c.phase});
  return h;
}

void validate(const TabulatedBase& b) {
  if (b.times.size() < 2 || b.times.size() != b.positions.size())
    throw ModelError(
        "base motion 'tabulated': need at least 2 samples and as many positions as times (got " +
        std::to_string(b.times.size()) + " times, " + std::to_string(b.positions.size()) +
        " positions)", kBaseName);
  for (std::size_t k = 0; k < b.times.size(); ++k) {
    if (!std::isfinite(b.times[k]) || !finite(b.positions[k]))
      throw ModelError("base motion 'tabulated': sample " + std::to_string(k + 1) +
                       " is not finite", kBaseName);
    if (k > 0 && !(b.times[k] > b.times[k - 1]))
      throw ModelError("base motion 'tabulated': times must be strictly increasing (sample " +
                       std::to_string(k + 1) + ")", kBaseName);
  }
}

// Natural cubic spline moments (second derivatives at the knots), per axis at
// once, by the tridiagonal (Thomas) algorithm.
std::vector<Vec3> spline_moments(const TabulatedBase& b) {
  const std::size_t n = b.times.size();
  std::vector<Vec3> m(n, Vec3::Zero());
  if (n < 3) return m;
  std::vector<double> diag(n, 0.0), upper(n, 0.0);
  std::vector<Vec3> rhs(n, Vec3::Zero());
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double h0 = b.times[i] - b.times[i - 1];
    const double h1 = b.times[i + 1] - b.times[i];
    diag[i] = 2.0 * (h0 + h1);
    upper[i] = h1;
    rhs[i] = 6.0 * ((b.positions[i + 1] - b.positions[i]) / h1 -
                    (b.positions[i] - b.positions[i - 1]) / h0);
  }
  // Forward elimination on rows 1..n-2 (m_0 = m_{n-1} = 0).
  for (std::size_t i = 2; i + 1 < n; ++i) {
    const double lower = b.times[i] - b.times[i - 1];
    const double f = lower / diag[i - 1];
    diag[i] -= f * upper[i - 1];
    rhs[i] -= f * rhs[i - 1];
  }
  for (std::size_t i = n - 2; i >= 1; --i) {
    m[i] = (rhs[i] - upper[i] * m[i + 1]) / diag[i];
  }
  return m;
}

}  // namespace

BaseMotion::BaseMotion(BaseMotionSpec spec) {
  std::visit([](const auto& b) { validate(b); }, spec);
  if (auto* tab = std::get_if<TabulatedBase>(&spec)) {
    std::vector<Vec3> moments = spline_moments(*tab);
    motion_ = std::make_shared<const Spline>(Spline{std::move(*tab), std::move(moments)});
  } else if (auto* f = std::get_if<FixedBase>(&spec)) {
    motion_ = *f;
  } else if (auto* c = std::get_if<ConstantAccelerationBase>(&spec)) {
    motion_ = *c;
  } else if (auto* sea = std::get_if<SeaStateBase>(&spec)) {
    motion_ = compile(*sea);
  } else {
    motion_ = std::move(std::get<HarmonicBase>(spec));
  }
}

bool BaseMotion::is_fixed() const {
  if (std::holds_alternative<FixedBase>(motion_)) return true;
  if (const auto* c = std::get_if<ConstantAccelerationBase>(&motion_))
    return c->velocity.isZero(0.0) && c->acceleration.isZero(0.0);
  if (const auto* h = std::get_if<HarmonicBase>(&motion_)) {
    for (const auto& axis : h->axes)
      for (const auto& term : axis)
        if (term.amplitude != 0.0 && term.frequency != 0.0) return false;
    return true;
  }
  return false;
}

BaseKinematics BaseMotion::at(double t) const {
  BaseKinematics k;
  if (const auto* f = std::get_if<FixedBase>(&motion_)) {
    k.position = f->position;
  } else if (const auto* c = std::get_if<ConstantAccelerationBase>(&motion_)) {
    k.position = c->position + c->velocity * t + 0.5 * c->acceleration * t * t;
    k.velocity = c->velocity + c->acceleration * t;
    k.acceleration = c->acceleration;
  } else if (const auto* harmonic = std::get_if<HarmonicBase>(&motion_)) {
    k.position = harmonic->offset;
    for (int axis = 0; axis < 3; ++axis) {
      for (const Harmonic& term : harmonic->axes[axis]) {
        const double omega = 2.0 * std::numbers::pi * term.frequency;
        const double s = std::sin(omega * t + term.phase);
        const double c2 = std::cos(omega * t + term.phase);
        k.position[axis] += term.amplitude * s;
        k.velocity[axis] += term.amplitude * omega * c2;
        k.acceleration[axis] -= term.amplitude * omega * omega * s;
      }
    }
  } else {
    const Spline& spline = *std::get<std::shared_ptr<const Spline>>(motion_);
    const auto& tab = spline.table;
    const auto& ts = tab.times;
    const auto& m = spline.moments;
    const std::size_t n = ts.size();
    auto slope_at_end = [&](std::size_t i0, std::size_t i1, bool left_end) {
      const double h = ts[i1] - ts[i0];
      const Vec3 secant = (tab.positions[i1] - tab.positions[i0]) / h;
      return left_end ? Vec3(secant - h * (2.0 * m[i0] + m[i1]) / 6.0)
                      : Vec3(secant + h * (m[i0] + 2.0 * m[i1]) / 6.0);
    };
    if (t <= ts.front()) {
      k.velocity = slope_at_end(0, 1, true);
      k.position = tab.positions.front() + k.velocity * (t - ts.front());
    } else if (t >= ts.back()) {
      k.velocity = slope_at_end(n - 2, n - 1, false);
      k.position = tab.positions.back() + k.velocity * (t - ts.back());
    } else {
      const std::size_t i1 =
          static_cast<std::size_t>(std::upper_bound(ts.begin(), ts.end(), t) - ts.begin());
      const std::size_t i0 = i1 - 1;
      const double h = ts[i1] - ts[i0];
      const double a = (ts[i1] - t) / h;
      const double b = (t - ts[i0]) / h;
      const Vec3& y0 = tab.positions[i0];
      const Vec3& y1 = tab.positions[i1];
      k.position = a * y0 + b * y1 + ((a * a * a - a) * m[i0] + (b * b * b - b) * m[i1]) * h * h / 6.0;
      k.velocity = (y1 - y0) / h - (3.0 * a * a - 1.0) * h / 6.0 * m[i0] +
                   (3.0 * b * b - 1.0) * h / 6.0 * m[i1];
      k.acceleration = a * m[i0] + b * m[i1];
    }
  }
  return k;
}

}  // namespace treedyn
