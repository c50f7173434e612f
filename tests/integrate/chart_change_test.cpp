// Chart changes of the angle sets cost no accuracy. They happen at the end of
// an accepted step, on the integrator's own state (not on an interpolant), so
// a restart is as accurate as a step: on a chaotic 5-body tree under harmonic
// base motion, bryant123 and euler313 end within 10x of the quaternion run's
// final-orientation error, with either ERK pair, against a tight reference.
// (Before, the restart at an interpolated root added ~1000 x rtol each time:
// bryant123 with erk_verner at rtol 1e-12 was off by 2.6e-6 rad at t = 2 s
// after 16 changes, the quaternion run by 2e-9.) Also: every chart change is
// logged with its time and body, and the log adds up to the counter.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "dynamics/recovered.hpp"
#include "integrate/simulate.hpp"
#include "model/model.hpp"
#include "support/random_tree.hpp"

namespace treedyn {
namespace {

constexpr int kBodies = 5;
constexpr double kEnd = 4.0;

ModelSpec chaotic_tree() {
  std::mt19937_64 rng(5150);
  testing::RandomTreeOptions options;
  options.bodies = kBodies;
  ModelSpec spec = testing::random_tree(rng, options);
  HarmonicBase base;
  base.axes[0].push_back({0.05, 2.0, 0.3});
  base.axes[2].push_back({0.08, 3.0, 0.0});
  spec.base_motion = base;
  return spec;
}

struct Final {
  IntegrationOutcome outcome;
  std::vector<Mat3> rotation;  // at kEnd, user order
};

Final run(const Model& model, const InitialState& initial, Parameterisation p, Method m, double tol) {
  SimulationRequest request;
  request.output_times = {kEnd};
  request.parameterisation = p;
  request.settings.method = m;
  request.settings.relative_tolerance = tol;
  request.settings.absolute_tolerance = tol;
  request.settings.max_steps = 10'000'000;
  Final f;
  f.outcome =
      simulate(model, initial, request, [&](const Model& mo, const Data& d) { f.rotation = recover(mo, d).rotation; });
  return f;
}

double worst_angle(const std::vector<Mat3>& a, const std::vector<Mat3>& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, testing::rotation_distance(a[i], b[i]));
  return worst;
}

// Tolerance: 10x the quaternion run's error, as the issue asks; the
// reference is direction cosines (no chart changes) with erk_verner at
// 1e-15, whose own error is ~1e-12 here, far below the 1e-12-tolerance runs'
// errors of ~1e-10..1e-9 that are compared.
TEST(ChartChange, AngleSetsAreAsAccurateAsQuaternionsWithBothErkPairs) {
  const Model model = build_model(chaotic_tree());
  std::mt19937_64 rng(77);
  const InitialState initial = testing::random_state(rng, kBodies, 12.0);
  const Final reference = run(model, initial, Parameterisation::direction_cosines, Method::erk_verner, 1e-15);
  ASSERT_TRUE(reference.outcome.ok()) << reference.outcome.message;
  // The reference itself, against a second tight run in other coordinates.
  const Final check = run(model, initial, Parameterisation::quaternion, Method::erk_verner, 1e-15);
  ASSERT_TRUE(check.outcome.ok());
  const double reference_spread = worst_angle(check.rotation, reference.rotation);
  std::printf("reference spread (quaternion vs direction cosines at 1e-15): %.2e rad\n", reference_spread);

  for (Method m : {Method::erk_verner, Method::erk_dormand_prince}) {
    const Final quaternion = run(model, initial, Parameterisation::quaternion, m, 1e-12);
    ASSERT_TRUE(quaternion.outcome.ok()) << quaternion.outcome.message;
    const double q_err = worst_angle(quaternion.rotation, reference.rotation);
    ASSERT_GT(q_err, 10.0 * reference_spread) << "the reference is not tight enough to judge";
    for (Parameterisation p : {Parameterisation::bryant123, Parameterisation::euler313}) {
      const Final angles = run(model, initial, p, m, 1e-12);
      ASSERT_TRUE(angles.outcome.ok()) << angles.outcome.message;
      const double err = worst_angle(angles.rotation, reference.rotation);
      std::printf("%-18s %-10s error %.2e rad, quaternion %.2e rad, ratio %.2f, %ld chart changes\n",
                  std::string(name(m)).c_str(), std::string(name(p)).c_str(), err, q_err, err / q_err,
                  angles.outcome.stats.chart_changes);
      EXPECT_GT(angles.outcome.stats.chart_changes, 5) << "the case must exercise chart changes";
      EXPECT_LT(err, 10.0 * q_err) << name(m) << " " << name(p);
    }
  }
}

TEST(ChartChange, EveryChangeIsLoggedWithItsTimeAndBody) {
  const Model model = build_model(chaotic_tree());
  std::mt19937_64 rng(77);
  const InitialState initial = testing::random_state(rng, kBodies, 12.0);
  const Final f = run(model, initial, Parameterisation::euler313, Method::cvode_adams, 1e-10);
  ASSERT_TRUE(f.outcome.ok());
  const auto& log = f.outcome.chart_changes;
  ASSERT_EQ(static_cast<long>(log.size()), f.outcome.stats.chart_changes);
  ASSERT_FALSE(log.empty());
  // One restart per step end that changed any chart, however many bodies.
  long distinct_times = 0;
  for (std::size_t k = 0; k < log.size(); ++k)
    if (k == 0 || log[k].time != log[k - 1].time) ++distinct_times;
  EXPECT_EQ(f.outcome.stats.restarts, distinct_times);
  for (std::size_t k = 0; k < log.size(); ++k) {
    EXPECT_GT(log[k].time, 0.0);
    EXPECT_LT(log[k].time, kEnd);
    EXPECT_GE(log[k].body, 0);
    EXPECT_LT(log[k].body, kBodies);
    if (k > 0) {
      EXPECT_LE(log[k - 1].time, log[k].time);
    }
  }
}

}  // namespace
}  // namespace treedyn
