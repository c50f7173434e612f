// The joint spring laws in motion:
//
//  * a torsional pendulum (one body on the base, the joint at its centre of
//    mass, turning about a principal axis) against its closed forms, started
//    150 degrees from rest so the laws differ: the rotation-vector law gives
//    C theta'' = -k theta, exactly theta0 cos(w t) at any amplitude; the
//    quaternion law gives C theta'' = -k sin(theta), the pendulum equation,
//    theta = 2 asin(m sn(K(m) - w t, m)) with m = sin(theta0 / 2);
//  * energy conservation (kinetic + gravity + spring) on random trees with
//    anisotropic springs and random reference orientations, for each law.
#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "dynamics/recovered.hpp"
#include "integrate/simulate.hpp"
#include "model/model.hpp"
#include "support/random_tree.hpp"

namespace treedyn {
namespace {

constexpr double kPi = std::numbers::pi;

struct SpringRun {
  IntegrationOutcome outcome;
  std::vector<Recovered> states;
};

SpringRun simulate_all(const ModelSpec& spec, const InitialState& initial, const std::vector<double>& times) {
  const Model model = build_model(spec);
  SimulationRequest request;
  request.settings.relative_tolerance = 1e-12;
  request.settings.absolute_tolerance = 1e-12;
  request.output_times = times;
  SpringRun r;
  r.outcome =
      simulate(model, initial, request, [&](const Model& m, const Data& d) { r.states.push_back(recover(m, d)); });
  return r;
}

ModelSpec torsional_pendulum(SpringLaw law, double k, double C) {
  ModelSpec spec;
  BodySpec wheel;
  wheel.name = "wheel";
  wheel.mass = 1.0;
  wheel.inertia = Vec3(0.3, 0.3, C).asDiagonal();
  spec.bodies.push_back(wheel);
  JointSpec j;
  j.parent = kBaseName;
  j.child = "wheel";  // the joint at the CoM: gravity exerts no moment about it
  j.spring.stiffness = k * Mat3::Identity();
  j.spring.law = law;
  spec.joints.push_back(j);
  return spec;
}

// Tolerance 1e-8 rad over 3 periods at rtol = atol = 1e-12 (the integrator's
// global error; the closed forms are exact to ~1e-15).
TEST(SpringLaw, TorsionalPendulumFollowsItsClosedForm) {
  const double k = 5.0, C = 0.2, theta0 = 150.0 * kPi / 180.0;
  const double w = std::sqrt(k / C);
  InitialState initial;
  initial.rotation = {Eigen::AngleAxisd(theta0, Vec3::UnitZ()).toRotationMatrix()};
  initial.angular_velocity = {Vec3::Zero()};
  std::vector<double> times;
  for (int s = 0; s <= 300; ++s) times.push_back(3.0 * (2.0 * kPi / w) * s / 300.0);

  for (SpringLaw law : {SpringLaw::rotation_vector, SpringLaw::quaternion}) {
    const SpringRun r = simulate_all(torsional_pendulum(law, k, C), initial, times);
    ASSERT_TRUE(r.outcome.ok()) << r.outcome.message;
    const double m = std::sin(theta0 / 2.0);
    const double K = boost::math::ellint_1(m);
    double worst = 0.0;
    for (std::size_t s = 0; s < times.size(); ++s) {
      const Mat3& A = r.states[s].rotation[0];
      const double angle = std::atan2(A(1, 0), A(0, 0));
      const double expected = law == SpringLaw::rotation_vector
                                  ? theta0 * std::cos(w * times[s])
                                  : 2.0 * std::asin(m * boost::math::jacobi_sn(m, K - w * times[s]));
      worst = std::max(worst, std::abs(angle - expected));
      // The motion stays about z.
      EXPECT_LT(std::abs(A(2, 2) - 1.0), 1e-10);
    }
    std::printf("%-16s max |theta - closed form| = %.2e rad over %zu outputs\n", std::string(name(law)).c_str(), worst,
                times.size());
    EXPECT_LT(worst, 1e-8) << name(law);
  }
}

// Largest angle of a joint's deviation from its reference.
double max_deviation(const ModelSpec& spec, const Recovered& s) {
  double out = 0.0;
  for (const JointSpec& j : spec.joints) {
    int c = -1, p = -1;
    for (std::size_t b = 0; b < spec.bodies.size(); ++b) {
      if (spec.bodies[b].name == j.child) c = static_cast<int>(b);
      if (spec.bodies[b].name == j.parent) p = static_cast<int>(b);
    }
    const Mat3 parent = p < 0 ? Mat3::Identity() : s.rotation[p];
    const Mat3 D = j.spring.reference.toRotationMatrix().transpose() * parent.transpose() * s.rotation[c];
    out = std::max(out, Eigen::AngleAxisd(D).angle());
  }
  return out;
}

// Random trees of 2 to 6 bodies with an anisotropic spring on every joint
// (random SPD, eigenvalues from `k_min` up), gravity, fixed base, no damping;
// each joint's reference is its initial relative orientation turned by up to
// `offset` rad. Returns the relative energy drift (max |E - E0| / (T + |V| +
// V_spring) at t = 0) and the largest deviation seen, per tree.
struct Conservation {
  double drift = 0.0, largest_deviation = 0.0;
};
std::vector<Conservation> conservation(SpringLaw law, double k_min, double offset, double spin, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> times;
  for (int s = 0; s <= 200; ++s) times.push_back(5.0 * s / 200.0);
  std::vector<Conservation> out;
  for (int n = 2; n <= 6; ++n) {
    testing::RandomTreeOptions options;
    options.bodies = n;
    ModelSpec spec = testing::random_tree(rng, options);
    const InitialState initial = testing::random_state(rng, n, spin);
    auto body = [&](const std::string& name) -> Mat3 {
      for (std::size_t b = 0; b < spec.bodies.size(); ++b)
        if (spec.bodies[b].name == name) return initial.rotation[b];
      return Mat3::Identity();  // the base
    };
    for (JointSpec& j : spec.joints) {
      Mat3 a;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) a(r, c) = u(rng);
      j.spring.stiffness = k_min * (a * a.transpose() + Mat3::Identity());
      const Mat3 relative = body(j.parent).transpose() * body(j.child);
      const Vec3 turn = testing::random_vector(rng, 1.0).normalized() * offset * std::abs(u(rng));
      j.spring.reference = Quat(relative * Eigen::AngleAxisd(turn.norm(), turn.normalized()).toRotationMatrix());
      j.spring.law = law;
    }
    const SpringRun r = simulate_all(spec, initial, times);
    EXPECT_TRUE(r.outcome.ok()) << r.outcome.message;
    if (!r.outcome.ok()) continue;
    const Energies& e0 = r.states.front().energy;
    const double scale = e0.kinetic + std::abs(e0.potential) + e0.spring;
    Conservation c;
    for (const Recovered& s : r.states) {
      c.drift = std::max(c.drift, std::abs(s.energy.total() - e0.total()) / scale);
      c.largest_deviation = std::max(c.largest_deviation, max_deviation(spec, s));
    }
    std::printf("%-16s n=%d  relative energy drift %.2e, largest deviation %.0f deg\n", std::string(name(law)).c_str(),
                n, c.drift, c.largest_deviation * 180.0 / kPi);
    out.push_back(c);
  }
  return out;
}

// Both laws, joints kept well inside 180 degrees (stiff springs, references
// up to 45 degrees from the start, spins up to 1 rad/s): energy constant to
// 1e-8 relative over 5 s at rtol = atol = 1e-12 (measured 1e-11 to 1e-9).
TEST(SpringLaw, EnergyIsConservedWithAnisotropicSprings) {
  for (SpringLaw law : {SpringLaw::quaternion, SpringLaw::rotation_vector}) {
    for (const Conservation& c : conservation(law, 40.0, kPi / 4.0, 1.0, 20261201)) {
      EXPECT_LT(c.largest_deviation, 0.9 * kPi) << name(law) << ": the case must stay inside 180 deg";
      EXPECT_LT(c.drift, 1e-8) << name(law);
    }
  }
}

// The quaternion law is smooth on all of SO(3): with soft springs, any
// reference and spins up to 2 rad/s the joints swing through 180 degrees,
// and energy is still constant to 1e-8 (the rotation-vector law's moment
// jumps there, so it is not held to this).
TEST(SpringLaw, QuaternionLawConservesEnergyThroughHalfTurns) {
  double largest = 0.0;
  for (const Conservation& c : conservation(SpringLaw::quaternion, 1.0, kPi, 2.0, 20261202)) {
    EXPECT_LT(c.drift, 1e-8);
    largest = std::max(largest, c.largest_deviation);
  }
  EXPECT_GT(largest, 0.95 * kPi) << "the case should pass close to 180 degrees";
}

}  // namespace
}  // namespace treedyn
