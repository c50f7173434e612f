// simulate(): every method reaches the same answer, outputs come from dense
// output (not from forced steps), failures come back typed with the time
// reached, and the statistics add up across chart-change restarts.
#include "integrate/simulate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "dynamics/recovered.hpp"
#include "model/model.hpp"
#include "support/random_tree.hpp"

namespace treedyn {
namespace {

struct Recording {
  IntegrationOutcome outcome;
  std::vector<Recovered> states;
};

// What simulate() takes besides the model.
struct Request : SimulationRequest {
  InitialState initial;
};

Recording record_run(const Model& model, const Request& request) {
  Recording r;
  r.outcome = simulate(model, request.initial, request,
                       [&](const Model& m, const Data& d) { r.states.push_back(recover(m, d)); });
  return r;
}

Request tumbling_request(const Model& model, std::mt19937_64& rng, double end, int outputs) {
  Request request;
  request.initial = testing::random_state(rng, model.n, 4.0);
  for (int k = 0; k <= outputs; ++k) request.output_times.push_back(end * k / outputs);
  return request;
}

// All four methods integrate the same 4-body tree for 3 s at tight tolerances
// and agree on the final orientations to 1e-7 rad (each is converged to
// ~1e-9 here; the bound leaves room for the different error constants), and
// each conserves energy to 1e-7 relative.
TEST(Simulate, AllMethodsAgree) {
  std::mt19937_64 rng(11);
  testing::RandomTreeOptions options;
  options.bodies = 4;
  const Model model = build_model(testing::random_tree(rng, options));
  Request request = tumbling_request(model, rng, 3.0, 30);
  request.settings.relative_tolerance = 1e-11;
  request.settings.absolute_tolerance = 1e-11;
  std::vector<Recording> runs;
  for (Method m : {Method::cvode_adams, Method::cvode_bdf, Method::erk_dormand_prince, Method::erk_verner}) {
    request.settings.method = m;
    runs.push_back(record_run(model, request));
    ASSERT_TRUE(runs.back().outcome.ok()) << name(m) << ": " << runs.back().outcome.message;
    const auto& s = runs.back().states;
    const double scale = s.front().energy.kinetic + std::abs(s.front().energy.potential);
    EXPECT_LT(std::abs(s.back().energy.total() - s.front().energy.total()) / scale, 1e-7) << name(m);
    std::printf("%-20s steps %6ld  rhs %7ld  error-test failures %4ld\n", std::string(name(m)).c_str(),
                runs.back().outcome.stats.steps, runs.back().outcome.stats.rhs_evaluations,
                runs.back().outcome.stats.error_test_failures);
  }
  double worst = 0.0;
  for (std::size_t r = 1; r < runs.size(); ++r)
    for (int b = 0; b < model.n; ++b)
      worst = std::max(
          worst, testing::rotation_distance(runs[0].states.back().rotation[b], runs[r].states.back().rotation[b]));
  std::printf("largest final orientation difference between methods: %.2e rad\n", worst);
  EXPECT_LT(worst, 1e-7);
}

// Output times come from the integrator's interpolant: asking for 1000 output
// times instead of 2 must not change the steps taken (it would if outputs
// forced steps), and the interpolated states agree with a run that stops
// exactly there to the integration tolerance (1e-8 rad at rtol 1e-10).
TEST(Simulate, OutputsUseDenseOutputNotForcedSteps) {
  std::mt19937_64 rng(12);
  testing::RandomTreeOptions options;
  options.bodies = 3;
  const Model model = build_model(testing::random_tree(rng, options));
  for (Method m : {Method::cvode_adams, Method::erk_dormand_prince}) {
    Request few = tumbling_request(model, rng, 2.0, 1);
    few.settings.method = m;
    few.settings.relative_tolerance = few.settings.absolute_tolerance = 1e-10;
    Request many = few;
    many.output_times.clear();
    for (int k = 0; k <= 1000; ++k) many.output_times.push_back(2.0 * k / 1000);
    const Recording a = record_run(model, few), b = record_run(model, many);
    ASSERT_TRUE(a.outcome.ok() && b.outcome.ok());
    EXPECT_EQ(a.outcome.stats.steps, b.outcome.stats.steps) << name(m);
    EXPECT_EQ(b.states.size(), 1001u);
    // The midpoint through dense output vs a run whose last output is there.
    Request to_mid = few;
    to_mid.output_times = {1.0};
    const Recording c = record_run(model, to_mid);
    for (int i = 0; i < model.n; ++i)
      EXPECT_LT(testing::rotation_distance(b.states[500].rotation[i], c.states[0].rotation[i]), 1e-8) << name(m);
  }
}

// Too little work allowed: the outcome says too_much_work, with the time
// reached (before the end), the statistics so far, and no exception.
TEST(Simulate, TooMuchWorkIsATypedFailureWithTheTimeReached) {
  std::mt19937_64 rng(13);
  testing::RandomTreeOptions options;
  options.bodies = 3;
  const Model model = build_model(testing::random_tree(rng, options));
  for (Method m : {Method::cvode_adams, Method::erk_verner}) {
    Request request = tumbling_request(model, rng, 10.0, 1);
    request.settings.method = m;
    request.settings.max_steps = 20;
    int outputs = 0;
    const IntegrationOutcome o =
        simulate(model, request.initial, request, [&](const Model&, const Data&) { ++outputs; });
    EXPECT_FALSE(o.ok());
    EXPECT_EQ(o.failure, FailureKind::too_much_work) << name(m) << ": " << o.message;
    EXPECT_GT(o.time_reached, 0.0);
    EXPECT_LT(o.time_reached, 10.0);
    EXPECT_GE(o.stats.steps, 20);
    EXPECT_FALSE(o.message.empty());
    EXPECT_EQ(outputs, 1);  // t = 0 only
  }
}

// A state that is not finite fails as nonfinite_state (the right-hand side
// reports it; SUNDIALS gives up after retrying), never as a crash.
TEST(Simulate, NonFiniteStateIsATypedFailure) {
  std::mt19937_64 rng(14);
  testing::RandomTreeOptions options;
  options.bodies = 2;
  const Model model = build_model(testing::random_tree(rng, options));
  for (Method m : {Method::cvode_adams, Method::cvode_bdf, Method::erk_dormand_prince}) {
    Request request = tumbling_request(model, rng, 1.0, 1);
    request.settings.method = m;
    request.initial.angular_velocity[1].x() = std::numeric_limits<double>::quiet_NaN();
    const IntegrationOutcome o = simulate(model, request.initial, request, {});
    EXPECT_FALSE(o.ok()) << name(m);
    EXPECT_NE(o.failure, FailureKind::none);
    EXPECT_EQ(o.time_reached, 0.0) << name(m);
  }
}

// Malformed requests are programming errors: std::invalid_argument.
TEST(Simulate, MalformedRequestsThrow) {
  std::mt19937_64 rng(15);
  const Model model = build_model(testing::random_tree(rng, {}));
  Request request = tumbling_request(model, rng, 1.0, 2);
  request.output_times = {0.5, 0.2};
  EXPECT_THROW(simulate(model, request.initial, request, {}), std::invalid_argument);
  request.output_times = {0.5};
  request.settings.relative_tolerance = 0.0;
  EXPECT_THROW(simulate(model, request.initial, request, {}), std::invalid_argument);
}

// Chart changes restart the integrator; the reported statistics are the sum
// over all restarts (steps never go backwards): an Euler-angle run through
// gimbal lock reports at least as many steps as its restarts, and more steps
// than the quaternion run of the same motion needs for its first second.
TEST(Simulate, StatisticsAccumulateOverChartRestarts) {
  ModelSpec spec;
  spec.gravity = Vec3::Zero();
  spec.bodies.push_back(rigid_body("ball", 1.0, Mat3::Identity() * 0.1));
  JointSpec j;
  j.parent = kBaseName;
  j.child = "ball";
  spec.joints.push_back(j);
  const Model model = build_model(spec);
  Request request;
  // A generic axis from a tilted start: the Bryant rates blow up at every
  // passage near a2 = 90 deg, so the chart must change (about a principal
  // axis from E they stay finite and a step may go straight across).
  const Mat3 tilted = Eigen::AngleAxisd(0.7, Vec3(1.0, -2.0, 0.5).normalized()).toRotationMatrix();
  const Vec3 w(1.3, -2.1, 2.7);
  request.initial.rotation = {tilted};
  request.initial.angular_velocity = {w};
  for (int k = 0; k <= 10; ++k) request.output_times.push_back(0.5 * k);
  request.parameterisation = Parameterisation::bryant123;
  const Recording r = record_run(model, request);
  ASSERT_TRUE(r.outcome.ok());
  EXPECT_GT(r.outcome.stats.chart_changes, 0);
  EXPECT_EQ(r.outcome.stats.restarts, r.outcome.stats.chart_changes);
  EXPECT_GT(r.outcome.stats.steps, r.outcome.stats.restarts);
  EXPECT_GT(r.outcome.stats.rhs_evaluations, r.outcome.stats.steps);
  // The closed form: rotation about a fixed axis at constant rate.
  const Mat3 expected = Eigen::AngleAxisd(w.norm() * 5.0, w.normalized()).toRotationMatrix() * tilted;
  EXPECT_LT(testing::rotation_distance(r.states.back().rotation[0], expected), 1e-6);
}

}  // namespace
}  // namespace treedyn
