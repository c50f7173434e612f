// BaseMotion::at for every kind of prescribed base motion, checked against
// closed forms, finite differences and an independent natural-spline solve;
// invalid descriptions throw ModelError.
#include "model/base_motion.hpp"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "common/error.hpp"

namespace treedyn {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Central differences of position (for velocity) and of velocity (for
// acceleration), and the second difference of position (for acceleration).
struct Differences {
  Vec3 velocity;
  Vec3 acceleration_from_velocity;
  Vec3 acceleration_from_position;
};

Differences differences(const BaseMotion& motion, double t, double h) {
  const BaseKinematics lo = motion.at(t - h), mid = motion.at(t), hi = motion.at(t + h);
  return {(hi.position - lo.position) / (2.0 * h), (hi.velocity - lo.velocity) / (2.0 * h),
          (hi.position - 2.0 * mid.position + lo.position) / (h * h)};
}

#define EXPECT_VEC_NEAR(a, b, tol) \
  EXPECT_LT(((a) - (b)).norm(), (tol)) << "  " #a " = " << (a).transpose() << "\n  " #b " = " << (b).transpose()

// ------------------------------------------------------------------- fixed

TEST(BaseMotion, DefaultIsFixedAtOrigin) {
  const BaseMotion motion;
  EXPECT_TRUE(motion.is_fixed());
  const BaseKinematics k = motion.at(3.0);
  EXPECT_EQ(k.position, Vec3::Zero());
  EXPECT_EQ(k.velocity, Vec3::Zero());
  EXPECT_EQ(k.acceleration, Vec3::Zero());
}

TEST(BaseMotion, Fixed) {
  const BaseMotion motion(FixedBase{Vec3(1.0, -2.0, 3.5)});
  EXPECT_TRUE(motion.is_fixed());
  for (double t : {-10.0, 0.0, 0.3, 1e6}) {
    const BaseKinematics k = motion.at(t);
    EXPECT_EQ(k.position, Vec3(1.0, -2.0, 3.5));
    EXPECT_EQ(k.velocity, Vec3::Zero());
    EXPECT_EQ(k.acceleration, Vec3::Zero());
  }
}

// ---------------------------------------------------- constant acceleration

TEST(BaseMotion, ConstantAcceleration) {
  const Vec3 r(1.0, 2.0, 3.0), v(-0.5, 0.25, 2.0), a(0.0, 3.0, -9.0);
  const BaseMotion motion(ConstantAccelerationBase{r, v, a});
  EXPECT_FALSE(motion.is_fixed());
  for (double t : {-1.5, 0.0, 0.7, 4.0}) {
    const BaseKinematics k = motion.at(t);
    EXPECT_VEC_NEAR(k.position, Vec3(r + v * t + 0.5 * a * t * t), 1e-13);
    EXPECT_VEC_NEAR(k.velocity, Vec3(v + a * t), 1e-13);
    EXPECT_VEC_NEAR(k.acceleration, a, 0.0 + 1e-15);
    const Differences d = differences(motion, t, 1e-3);  // exact for a quadratic, up to rounding
    EXPECT_VEC_NEAR(k.velocity, d.velocity, 1e-9);
    EXPECT_VEC_NEAR(k.acceleration, d.acceleration_from_velocity, 1e-9);
    EXPECT_VEC_NEAR(k.acceleration, d.acceleration_from_position, 1e-6);
  }
  EXPECT_TRUE(BaseMotion(ConstantAccelerationBase{r, Vec3::Zero(), Vec3::Zero()}).is_fixed());
  EXPECT_FALSE(BaseMotion(ConstantAccelerationBase{r, Vec3::Zero(), a}).is_fixed());
}

// --------------------------------------------------------------- harmonics

HarmonicBase sample_harmonics() {
  HarmonicBase h;
  h.offset = Vec3(0.1, -0.2, 1.0);
  h.axes[0] = {{0.05, 2.0, 0.3}, {0.01, 7.5, -1.0}};
  h.axes[1] = {};
  h.axes[2] = {{0.2, 0.5, 0.0}, {0.03, 0.0, 0.8}};  // frequency 0: a constant shift
  return h;
}

TEST(BaseMotion, HarmonicClosedForm) {
  const HarmonicBase spec = sample_harmonics();
  const BaseMotion motion(spec);
  EXPECT_FALSE(motion.is_fixed());
  const double two_pi = 2.0 * std::numbers::pi;
  for (double t : {0.0, 0.123, 1.0, 2.71}) {
    const BaseKinematics k = motion.at(t);
    const Vec3 expected(0.1 + 0.05 * std::sin(two_pi * 2.0 * t + 0.3) + 0.01 * std::sin(two_pi * 7.5 * t - 1.0), -0.2,
                        1.0 + 0.2 * std::sin(two_pi * 0.5 * t) + 0.03 * std::sin(0.8));
    EXPECT_VEC_NEAR(k.position, expected, 1e-14);
    EXPECT_EQ(k.velocity.y(), 0.0);
    EXPECT_EQ(k.acceleration.y(), 0.0);
  }
}

TEST(BaseMotion, HarmonicDerivativesMatchFiniteDifferences) {
  const BaseMotion motion(sample_harmonics());
  for (double t = -0.5; t < 2.0; t += 0.137) {
    SCOPED_TRACE("t = " + std::to_string(t));
    const BaseKinematics k = motion.at(t);
    const Differences d = differences(motion, t, 1e-5);
    // |v| ~ 1 m/s, |a| ~ 30 m/s^2; central differences err by h^2 r''' / 6.
    EXPECT_VEC_NEAR(k.velocity, d.velocity, 1e-7);
    EXPECT_VEC_NEAR(k.acceleration, d.acceleration_from_velocity, 1e-5);
    const Differences coarse = differences(motion, t, 1e-4);
    EXPECT_VEC_NEAR(k.acceleration, coarse.acceleration_from_position, 1e-3);
  }
}

TEST(BaseMotion, HarmonicIsFixedOnlyWithoutMotion) {
  HarmonicBase h;
  h.offset = Vec3(1.0, 0.0, 0.0);
  EXPECT_TRUE(BaseMotion(h).is_fixed());
  h.axes[1] = {{0.0, 3.0, 0.0}, {0.5, 0.0, 1.0}};  // zero amplitude, zero frequency
  EXPECT_TRUE(BaseMotion(h).is_fixed());
  const BaseKinematics k = BaseMotion(h).at(0.4);
  EXPECT_EQ(k.velocity, Vec3::Zero());
  EXPECT_EQ(k.acceleration, Vec3::Zero());
  h.axes[2] = {{0.1, 1.0, 0.0}};
  EXPECT_FALSE(BaseMotion(h).is_fixed());
}

// ------------------------------------------------------------- tabulated

TabulatedBase sample_table() {
  TabulatedBase tab;
  tab.times = {-0.5, 0.0, 0.3, 1.1, 1.2, 2.0, 3.5};  // uneven spacing
  tab.positions = {Vec3(0.0, 1.0, -1.0), Vec3(0.4, 0.8, -0.5), Vec3(0.1, 0.9, 0.0), Vec3(-0.3, 1.5, 0.2),
                   Vec3(-0.2, 1.4, 0.3), Vec3(0.6, 0.7, 0.1),  Vec3(0.2, 0.2, -0.4)};
  return tab;
}

// Natural-spline moments from a dense solve of the standard tridiagonal system.
std::vector<Vec3> reference_moments(const TabulatedBase& tab) {
  const int n = static_cast<int>(tab.times.size());
  std::vector<Vec3> m(n, Vec3::Zero());
  if (n < 3) return m;
  const int k = n - 2;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(k, k);
  Eigen::MatrixXd rhs(k, 3);
  for (int i = 1; i <= k; ++i) {
    const double h0 = tab.times[i] - tab.times[i - 1], h1 = tab.times[i + 1] - tab.times[i];
    A(i - 1, i - 1) = 2.0 * (h0 + h1);
    if (i > 1) A(i - 1, i - 2) = h0;
    if (i < k) A(i - 1, i) = h1;
    rhs.row(i - 1) =
        (6.0 * ((tab.positions[i + 1] - tab.positions[i]) / h1 - (tab.positions[i] - tab.positions[i - 1]) / h0))
            .transpose();
  }
  const Eigen::MatrixXd x = A.partialPivLu().solve(rhs);
  for (int i = 1; i <= k; ++i) m[i] = x.row(i - 1).transpose();
  return m;
}

TEST(BaseMotion, TabulatedInterpolatesKnotsExactly) {
  const TabulatedBase tab = sample_table();
  const BaseMotion motion(tab);
  EXPECT_FALSE(motion.is_fixed());
  for (std::size_t i = 0; i < tab.times.size(); ++i)
    EXPECT_VEC_NEAR(motion.at(tab.times[i]).position, tab.positions[i], 1e-14) << "knot " << i;
}

TEST(BaseMotion, TabulatedMatchesReferenceNaturalSpline) {
  const TabulatedBase tab = sample_table();
  const BaseMotion motion(tab);
  const std::vector<Vec3> m = reference_moments(tab);
  // r'' at every knot is the spline moment (zero at both ends: natural).
  for (std::size_t i = 0; i < tab.times.size(); ++i) {
    const double t = tab.times[i];
    if (i == 0) {
      EXPECT_VEC_NEAR(motion.at(t + 1e-12).acceleration, m[i], 1e-9) << "knot " << i;
    } else {
      EXPECT_VEC_NEAR(motion.at(t - 1e-12).acceleration, m[i], 1e-9) << "knot " << i;
    }
  }
  EXPECT_EQ(m.front(), Vec3::Zero());
  EXPECT_EQ(m.back(), Vec3::Zero());
  // Between knots: the textbook cubic with these moments.
  for (std::size_t i = 0; i + 1 < tab.times.size(); ++i) {
    const double h = tab.times[i + 1] - tab.times[i];
    for (double s : {0.1, 0.5, 0.77}) {
      const double t = tab.times[i] + s * h;
      const double a = 1.0 - s, b = s;
      const Vec3 expected = a * tab.positions[i] + b * tab.positions[i + 1] +
                            ((a * a * a - a) * m[i] + (b * b * b - b) * m[i + 1]) * h * h / 6.0;
      EXPECT_VEC_NEAR(motion.at(t).position, expected, 1e-12) << "segment " << i << " s " << s;
    }
  }
}

TEST(BaseMotion, TabulatedIsC2AtKnots) {
  const TabulatedBase tab = sample_table();
  const BaseMotion motion(tab);
  const double eps = 1e-8;
  for (std::size_t i = 0; i < tab.times.size(); ++i) {
    SCOPED_TRACE("knot " + std::to_string(i));
    const BaseKinematics left = motion.at(tab.times[i] - eps);
    const BaseKinematics right = motion.at(tab.times[i] + eps);
    // Jumps of size O(eps * derivative bound) only; a discontinuity would be O(1).
    EXPECT_VEC_NEAR(left.position, right.position, 1e-6);
    EXPECT_VEC_NEAR(left.velocity, right.velocity, 1e-6);
    EXPECT_VEC_NEAR(left.acceleration, right.acceleration, 1e-5);
  }
}

TEST(BaseMotion, TabulatedDerivativesMatchFiniteDifferences) {
  const TabulatedBase tab = sample_table();
  const BaseMotion motion(tab);
  const double h = 1e-5;
  for (std::size_t i = 0; i + 1 < tab.times.size(); ++i) {
    const double t0 = tab.times[i], t1 = tab.times[i + 1];
    for (double s : {0.05, 0.3, 0.5, 0.9}) {
      const double t = t0 + s * (t1 - t0);
      SCOPED_TRACE("t = " + std::to_string(t));
      const BaseKinematics k = motion.at(t);
      const Differences d = differences(motion, t, h);
      EXPECT_VEC_NEAR(k.velocity, d.velocity, 1e-7);
      EXPECT_VEC_NEAR(k.acceleration, d.acceleration_from_velocity, 1e-6);
      const Differences coarse = differences(motion, t, 1e-4);
      EXPECT_VEC_NEAR(k.acceleration, coarse.acceleration_from_position, 1e-4);
    }
  }
  // Across the knots too. The spline is C2 but r''' jumps there, so the central
  // difference of the velocity is off by exactly h/4 (r'''+ - r'''-), with
  // r''' = (m_{i+1} - m_i) / h_i on segment i.
  const std::vector<Vec3> m = reference_moments(tab);
  for (std::size_t i = 1; i + 1 < tab.times.size(); ++i) {
    const BaseKinematics k = motion.at(tab.times[i]);
    const Differences d = differences(motion, tab.times[i], h);
    const Vec3 jerk_left = (m[i] - m[i - 1]) / (tab.times[i] - tab.times[i - 1]);
    const Vec3 jerk_right = (m[i + 1] - m[i]) / (tab.times[i + 1] - tab.times[i]);
    EXPECT_VEC_NEAR(k.velocity, d.velocity, 1e-7) << "knot " << i;
    EXPECT_VEC_NEAR(Vec3(k.acceleration + h / 4.0 * (jerk_right - jerk_left)), d.acceleration_from_velocity, 1e-6)
        << "knot " << i;
  }
}

TEST(BaseMotion, TabulatedExtrapolatesLinearly) {
  const TabulatedBase tab = sample_table();
  const BaseMotion motion(tab);
  const double first = tab.times.front(), last = tab.times.back();
  const Vec3 v_first = motion.at(first + 1e-9).velocity;
  const Vec3 v_last = motion.at(last - 1e-9).velocity;
  EXPECT_VEC_NEAR(motion.at(first).velocity, v_first, 1e-7);
  EXPECT_VEC_NEAR(motion.at(last).velocity, v_last, 1e-7);
  for (double dt : {1e-6, 0.1, 1.0, 25.0}) {
    SCOPED_TRACE("dt = " + std::to_string(dt));
    const BaseKinematics before = motion.at(first - dt);
    EXPECT_VEC_NEAR(before.position, Vec3(tab.positions.front() - v_first * dt), 1e-7 * (1.0 + dt));
    EXPECT_VEC_NEAR(before.velocity, v_first, 1e-7);
    EXPECT_EQ(before.acceleration, Vec3::Zero());
    const BaseKinematics after = motion.at(last + dt);
    EXPECT_VEC_NEAR(after.position, Vec3(tab.positions.back() + v_last * dt), 1e-7 * (1.0 + dt));
    EXPECT_VEC_NEAR(after.velocity, v_last, 1e-7);
    EXPECT_EQ(after.acceleration, Vec3::Zero());
  }
  // Natural end conditions: r'' -> 0 at both ends from inside.
  EXPECT_VEC_NEAR(motion.at(first + 1e-9).acceleration, Vec3::Zero(), 1e-6);
  EXPECT_VEC_NEAR(motion.at(last - 1e-9).acceleration, Vec3::Zero(), 1e-6);
}

TEST(BaseMotion, TabulatedTwoSamplesIsAStraightLine) {
  TabulatedBase tab;
  tab.times = {1.0, 3.0};
  tab.positions = {Vec3(0.0, 0.0, 0.0), Vec3(2.0, -4.0, 1.0)};
  const BaseMotion motion(tab);
  const Vec3 v(1.0, -2.0, 0.5);
  for (double t : {-1.0, 1.0, 1.5, 2.999, 3.0, 7.0}) {
    const BaseKinematics k = motion.at(t);
    EXPECT_VEC_NEAR(k.position, Vec3(v * (t - 1.0)), 1e-14) << "t " << t;
    EXPECT_VEC_NEAR(k.velocity, v, 1e-14) << "t " << t;
    EXPECT_EQ(k.acceleration, Vec3::Zero()) << "t " << t;
  }
}

TEST(BaseMotion, TabulatedReproducesLinearData) {
  TabulatedBase tab;
  const Vec3 r0(0.5, -1.0, 2.0), v(0.3, 0.1, -0.7);
  for (double t : {0.0, 0.1, 0.5, 0.55, 2.0}) {
    tab.times.push_back(t);
    tab.positions.push_back(r0 + v * t);
  }
  const BaseMotion motion(tab);
  for (double t = -1.0; t < 3.0; t += 0.093) {
    const BaseKinematics k = motion.at(t);
    EXPECT_VEC_NEAR(k.position, Vec3(r0 + v * t), 1e-13) << "t " << t;
    EXPECT_VEC_NEAR(k.velocity, v, 1e-13) << "t " << t;
    EXPECT_VEC_NEAR(k.acceleration, Vec3::Zero(), 1e-12) << "t " << t;
  }
}

// ------------------------------------------------------------ invalid specs

std::string motion_error(const BaseMotionSpec& spec) {
  try {
    BaseMotion motion(spec);
  } catch (const ModelError& e) {
    return e.what();
  } catch (...) {
    ADD_FAILURE() << "expected ModelError, got another exception";
    return "";
  }
  ADD_FAILURE() << "expected ModelError, the base motion was accepted";
  return "";
}

#define EXPECT_MESSAGE_HAS(message, part) \
  EXPECT_NE((message).find(part), std::string::npos) << "message: \"" << (message) << "\"\nlacks: \"" << (part) << "\""

TEST(BaseMotionInvalid, TabulatedNonIncreasingTimes) {
  TabulatedBase tab = sample_table();
  tab.times[3] = tab.times[2];  // repeated
  std::string msg = motion_error(tab);
  EXPECT_MESSAGE_HAS(msg, "strictly increasing");
  EXPECT_MESSAGE_HAS(msg, "sample 4");
  tab = sample_table();
  tab.times[5] = 0.9;  // decreasing
  msg = motion_error(tab);
  EXPECT_MESSAGE_HAS(msg, "strictly increasing");
  EXPECT_MESSAGE_HAS(msg, "sample 6");
}

TEST(BaseMotionInvalid, TabulatedMismatchedSizes) {
  TabulatedBase tab = sample_table();
  tab.positions.pop_back();
  std::string msg = motion_error(tab);
  EXPECT_MESSAGE_HAS(msg, "7 times, 6 positions");
  tab = sample_table();
  tab.times.pop_back();
  msg = motion_error(tab);
  EXPECT_MESSAGE_HAS(msg, "6 times, 7 positions");
}

TEST(BaseMotionInvalid, TabulatedTooFewSamples) {
  TabulatedBase tab;
  EXPECT_MESSAGE_HAS(motion_error(tab), "at least 2");
  tab.times = {0.0};
  tab.positions = {Vec3::Zero()};
  EXPECT_MESSAGE_HAS(motion_error(tab), "at least 2");
}

TEST(BaseMotionInvalid, TabulatedNaN) {
  TabulatedBase tab = sample_table();
  tab.times[2] = kNaN;
  EXPECT_MESSAGE_HAS(motion_error(tab), "sample 3 is not finite");
  tab = sample_table();
  tab.positions[4].y() = kNaN;
  EXPECT_MESSAGE_HAS(motion_error(tab), "sample 5 is not finite");
  tab = sample_table();
  tab.positions[0].z() = kInf;
  EXPECT_MESSAGE_HAS(motion_error(tab), "sample 1 is not finite");
}

TEST(BaseMotionInvalid, HarmonicNegativeFrequency) {
  HarmonicBase h = sample_harmonics();
  h.axes[2][1].frequency = -1.0;
  const std::string msg = motion_error(h);
  EXPECT_MESSAGE_HAS(msg, "axis z term 2");
  EXPECT_MESSAGE_HAS(msg, "frequency");
}

TEST(BaseMotionInvalid, HarmonicNaN) {
  HarmonicBase h = sample_harmonics();
  h.axes[0][0].frequency = kNaN;
  EXPECT_MESSAGE_HAS(motion_error(h), "axis x term 1");
  h = sample_harmonics();
  h.axes[0][1].amplitude = kNaN;
  EXPECT_MESSAGE_HAS(motion_error(h), "amplitude");
  h = sample_harmonics();
  h.axes[2][0].phase = kInf;
  EXPECT_MESSAGE_HAS(motion_error(h), "phase");
  h = sample_harmonics();
  h.axes[0][0].frequency = kInf;
  EXPECT_MESSAGE_HAS(motion_error(h), "frequency");
  h = sample_harmonics();
  h.offset.x() = kNaN;
  EXPECT_MESSAGE_HAS(motion_error(h), "offset");
}

TEST(BaseMotionInvalid, FixedAndConstantAccelerationNaN) {
  EXPECT_MESSAGE_HAS(motion_error(FixedBase{Vec3(kNaN, 0.0, 0.0)}), "fixed");
  EXPECT_MESSAGE_HAS(motion_error(ConstantAccelerationBase{Vec3::Zero(), Vec3(0.0, kInf, 0.0), Vec3::Zero()}),
                     "constant_acceleration");
  EXPECT_MESSAGE_HAS(motion_error(ConstantAccelerationBase{Vec3::Zero(), Vec3::Zero(), Vec3(0.0, 0.0, kNaN)}),
                     "constant_acceleration");
}

}  // namespace
}  // namespace treedyn
