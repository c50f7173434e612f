// recover() computes only the parts a recorder asks for, and simulate() runs
// only the kinematics and loads at the output times when no accelerations
// are asked for (dynamics/recovered.hpp, integrate/simulate.hpp). What is
// computed must be the same bits as with everything on: the same trajectory
// observed both ways on random trees with springs, with both solvers, and
// every part alone. Exact (==), since the same operations run on the same
// integrated states.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "dynamics/recovered.hpp"
#include "integrate/simulate.hpp"
#include "model/model.hpp"
#include "support/random_tree.hpp"

namespace treedyn {
namespace {

std::vector<Recovered> observe(const Model& model, const InitialState& state, SimulationRequest request,
                               unsigned parts) {
  request.accelerations_at_outputs = (parts & kRecoverAccelerations) != 0;
  std::vector<Recovered> seen;
  const IntegrationOutcome outcome = simulate(model, state, request, [&](const Model& m, const Data& data) {
    Recovered r;
    recover(m, data, r, parts);
    seen.push_back(std::move(r));
  });
  EXPECT_TRUE(outcome.ok()) << outcome.message;
  return seen;
}

void expect_same_vectors(const std::vector<Vec3>& a, const std::vector<Vec3>& b, const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t u = 0; u < a.size(); ++u) EXPECT_TRUE(a[u] == b[u]) << what << " of body " << u;
}

// The parts `parts` asks for (and the always-recovered ones) of `part`
// equal those of `full`.
void expect_parts_equal(const Recovered& full, const Recovered& part, unsigned parts) {
  EXPECT_EQ(full.time, part.time);
  EXPECT_TRUE(full.base.position == part.base.position && full.base.acceleration == part.base.acceleration);
  for (std::size_t u = 0; u < full.rotation.size(); ++u) EXPECT_TRUE(full.rotation[u] == part.rotation[u]);
  expect_same_vectors(full.angular_velocity, part.angular_velocity, "w");
  expect_same_vectors(full.com_position, part.com_position, "r");
  expect_same_vectors(full.com_velocity, part.com_velocity, "r'");
  expect_same_vectors(full.joint_position, part.joint_position, "joint point");
  expect_same_vectors(full.joint_moment, part.joint_moment, "joint moment");
  if (parts & kRecoverAccelerations) {
    expect_same_vectors(full.angular_acceleration, part.angular_acceleration, "w'");
    expect_same_vectors(full.com_acceleration, part.com_acceleration, "r''");
    expect_same_vectors(full.joint_reaction, part.joint_reaction, "reaction");
  }
  if (parts & kRecoverJointAngles) {
    EXPECT_TRUE(full.joint_angle == part.joint_angle);
    expect_same_vectors(full.joint_axis, part.joint_axis, "joint axis");
  }
  if (parts & kRecoverEnergy) {
    EXPECT_EQ(full.energy.kinetic, part.energy.kinetic);
    EXPECT_EQ(full.energy.potential, part.energy.potential);
    EXPECT_EQ(full.energy.spring, part.energy.spring);
  } else {
    EXPECT_EQ(part.energy.total(), 0.0) << "a part not asked for is left at zero";
  }
  if (parts & kRecoverAngularMomentum) {
    EXPECT_TRUE(full.angular_momentum_about_base == part.angular_momentum_about_base);
  }
}

TEST(RecoveredParts, EachPartAloneIsTheSameBitsAsEverything) {
  std::mt19937_64 rng(20261202);
  for (const AccelerationSolver solver : {AccelerationSolver::recursive, AccelerationSolver::sparse_ldlt}) {
    testing::RandomTreeOptions options;
    options.bodies = 6;
    options.spring_stiffness = 2.0;
    options.spring_damping = 0.1;
    const Model model = build_model(testing::random_tree(rng, options));
    const InitialState state = testing::random_state(rng, options.bodies, 2.0);
    SimulationRequest request;
    request.solver = solver;
    for (int k = 0; k <= 20; ++k) request.output_times.push_back(0.05 * k);
    const std::vector<Recovered> full = observe(model, state, request, kRecoverEverything);
    for (const unsigned parts : {0u, unsigned{kRecoverAccelerations}, unsigned{kRecoverJointAngles},
                                 unsigned{kRecoverEnergy}, unsigned{kRecoverAngularMomentum}}) {
      const std::vector<Recovered> part = observe(model, state, request, parts);
      ASSERT_EQ(part.size(), full.size());
      for (std::size_t k = 0; k < full.size(); ++k) {
        SCOPED_TRACE(::testing::Message()
                     << "solver " << static_cast<int>(solver) << ", parts " << parts << ", output " << k);
        expect_parts_equal(full[k], part[k], parts);
      }
    }
  }
}

}  // namespace
}  // namespace treedyn
