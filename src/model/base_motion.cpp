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
    throw ModelError("base motion 'constant_acceleration': position, velocity and acceleration must be finite",
                     kBaseName);
}

void validate(const HarmonicBase& b) {
  if (!finite(b.offset)) throw ModelError("base motion 'harmonic': offset must be finite", kBaseName);
  static const char* axis_name[3] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    for (std::size_t k = 0; k < b.axes[axis].size(); ++k) {
      const Harmonic& h = b.axes[axis][k];
      const std::string where =
          std::string("base motion 'harmonic', axis ") + axis_name[axis] + " term " + std::to_string(k + 1) + ": ";
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

void validate(const TabulatedBase& b) {
  if (b.times.size() < 2 || b.times.size() != b.positions.size())
    throw ModelError("base motion 'tabulated': need at least 2 samples and as many positions as times (got " +
                         std::to_string(b.times.size()) + " times, " + std::to_string(b.positions.size()) +
                         " positions)",
                     kBaseName);
  for (std::size_t k = 0; k < b.times.size(); ++k) {
    if (!std::isfinite(b.times[k]) || !finite(b.positions[k]))
      throw ModelError("base motion 'tabulated': sample " + std::to_string(k + 1) + " is not finite", kBaseName);
    if (k > 0 && !(b.times[k] > b.times[k - 1]))
      throw ModelError(
          "base motion 'tabulated': times must be strictly increasing (sample " + std::to_string(k + 1) + ")",
          kBaseName);
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
    rhs[i] = 6.0 * ((b.positions[i + 1] - b.positions[i]) / h1 - (b.positions[i] - b.positions[i - 1]) / h0);
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
  if (const auto* sea = std::get_if<SeaMotion>(&motion_)) {
    for (const auto& axis : sea->axes)
      for (const auto& c : axis.c)
        if (c != 0.0) return false;
    return true;
  }
  return false;
}

BaseMotion::SeaMotion BaseMotion::compile(const SeaStateBase& sea) {
  SeaMotion m;
  m.offset = sea.offset;
  for (int axis = 0; axis < 3; ++axis) {
    if (!sea.axes[axis]) continue;
    const SeaStateAxis& a = *sea.axes[axis];
    const std::vector<SeaComponent> parts = components(a);
    EquispacedHarmonics& h = m.axes[axis];
    h.w0 = 2.0 * std::numbers::pi * parts.front().frequency;
    h.dw = 2.0 * std::numbers::pi * (a.max_frequency - a.min_frequency) / a.components();
    for (const SeaComponent& c : parts) h.c.push_back(std::polar(c.amplitude, c.phase));
  }
  return m;
}

BaseKinematics BaseMotion::kinematics(const FixedBase& b, double) {
  BaseKinematics k;
  k.position = b.position;
  return k;
}

BaseKinematics BaseMotion::kinematics(const ConstantAccelerationBase& c, double t) {
  BaseKinematics k;
  k.position = c.position + c.velocity * t + 0.5 * c.acceleration * t * t;
  k.velocity = c.velocity + c.acceleration * t;
  k.acceleration = c.acceleration;
  return k;
}

BaseKinematics BaseMotion::kinematics(const HarmonicBase& harmonic, double t) {
  BaseKinematics k;
  k.position = harmonic.offset;
  for (int axis = 0; axis < 3; ++axis) {
    for (const Harmonic& term : harmonic.axes[axis]) {
      const double omega = 2.0 * std::numbers::pi * term.frequency;
      const double s = std::sin(omega * t + term.phase);
      const double c2 = std::cos(omega * t + term.phase);
      k.position[axis] += term.amplitude * s;
      k.velocity[axis] += term.amplitude * omega * c2;
      k.acceleration[axis] -= term.amplitude * omega * omega * s;
    }
  }
  return k;
}

// u_k = c_k e^{i w_k t} = a_k e^{i (w_k t + phi_k)}: position Im u, velocity
// w Re u, acceleration -w^2 Im u. The recurrence rounds by about k/4 ulp at
// component k (1e-14 relative for 64 components), against one ulp for a
// sincos each; e^{i dw t} is evaluated afresh at every t, so nothing
// accumulates over time.
BaseKinematics BaseMotion::kinematics(const SeaMotion& sea, double t) {
  BaseKinematics k;
  k.position = sea.offset;
  for (int axis = 0; axis < 3; ++axis) {
    const EquispacedHarmonics& h = sea.axes[axis];
    if (h.c.empty()) continue;
    // Four interleaved recurrences (components n, n+1, n+2, n+3 step by
    // e^{4 i dw t}): one chain would wait on each product's latency. The
    // products are written out: std::complex's operator* checks for
    // infinities and NaN (Annex G) through a library call.
    const double sr = std::cos(h.dw * t), si = std::sin(h.dw * t);
    double zr[4], zi[4];
    zr[0] = std::cos(h.w0 * t);
    zi[0] = std::sin(h.w0 * t);
    for (int j = 1; j < 4; ++j) {
      zr[j] = zr[j - 1] * sr - zi[j - 1] * si;
      zi[j] = zr[j - 1] * si + zi[j - 1] * sr;
    }
    const double s2r = sr * sr - si * si, s2i = 2.0 * sr * si;
    const double s4r = s2r * s2r - s2i * s2i, s4i = 2.0 * s2r * s2i;
    double p[4] = {}, v[4] = {}, a[4] = {};
    for (std::size_t n = 0; n < h.c.size(); n += 4) {
      for (std::size_t j = 0; j < 4 && n + j < h.c.size(); ++j) {
        const double w = h.w0 + static_cast<double>(n + j) * h.dw;
        const std::complex<double> c = h.c[n + j];
        const double ur = c.real() * zr[j] - c.imag() * zi[j];
        const double ui = c.real() * zi[j] + c.imag() * zr[j];
        p[j] += ui;
        v[j] += w * ur;
        a[j] -= w * w * ui;
        const double next = zr[j] * s4r - zi[j] * s4i;
        zi[j] = zr[j] * s4i + zi[j] * s4r;
        zr[j] = next;
      }
    }
    k.position[axis] += (p[0] + p[1]) + (p[2] + p[3]);
    k.velocity[axis] = (v[0] + v[1]) + (v[2] + v[3]);
    k.acceleration[axis] = (a[0] + a[1]) + (a[2] + a[3]);
  }
  return k;
}

BaseKinematics BaseMotion::kinematics(const std::shared_ptr<const Spline>& shared, double t) {
  BaseKinematics k;
  const Spline& spline = *shared;
  const auto& tab = spline.table;
  const auto& ts = tab.times;
  const auto& m = spline.moments;
  const std::size_t n = ts.size();
  auto slope_at_end = [&](std::size_t i0, std::size_t i1, bool left_end) {
    const double h = ts[i1] - ts[i0];
    const Vec3 secant = (tab.positions[i1] - tab.positions[i0]) / h;
    return left_end ? Vec3(secant - h * (2.0 * m[i0] + m[i1]) / 6.0) : Vec3(secant + h * (m[i0] + 2.0 * m[i1]) / 6.0);
  };
  if (t <= ts.front()) {
    k.velocity = slope_at_end(0, 1, true);
    k.position = tab.positions.front() + k.velocity * (t - ts.front());
  } else if (t >= ts.back()) {
    k.velocity = slope_at_end(n - 2, n - 1, false);
    k.position = tab.positions.back() + k.velocity * (t - ts.back());
  } else {
    const std::size_t i1 = static_cast<std::size_t>(std::upper_bound(ts.begin(), ts.end(), t) - ts.begin());
    const std::size_t i0 = i1 - 1;
    const double h = ts[i1] - ts[i0];
    const double a = (ts[i1] - t) / h;
    const double b = (t - ts[i0]) / h;
    const Vec3& y0 = tab.positions[i0];
    const Vec3& y1 = tab.positions[i1];
    k.position = a * y0 + b * y1 + ((a * a * a - a) * m[i0] + (b * b * b - b) * m[i1]) * h * h / 6.0;
    k.velocity = (y1 - y0) / h - (3.0 * a * a - 1.0) * h / 6.0 * m[i0] + (3.0 * b * b - 1.0) * h / 6.0 * m[i1];
    k.acceleration = a * m[i0] + b * m[i1];
  }
  return k;
}

BaseKinematics BaseMotion::at(double t) const {
  return std::visit([t](const auto& motion) { return kinematics(motion, t); }, motion_);
}

}  // namespace treedyn
