// Morris' design and measures (src/designs/morris/) against what they must
// be by construction and against closed forms:
//
//  * the trajectories: consecutive runs differ in exactly one unit's
//    inputs, by exactly Delta = 1/2 in u, the way steps() says; every unit
//    moves once; every u is a level centre; run k is the same computed
//    alone; the levels are drawn uniformly;
//  * a linear response of uniform inputs: every elementary effect is its
//    coefficient times the input's range (exact up to rounding), so mu =
//    mu* = that and sigma = 0; with groups, the sum over the group;
//  * Sobol's g function, whose total indices are known in closed form: mu*
//    ranks the inputs as the total indices do, neighbours told apart;
//  * failed runs drop exactly the effects of their two steps.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <numeric>
#include <vector>

#include "designs/morris/morris_effects.hpp"
#include "designs/morris/morris_points.hpp"
#include "designs/sample_design.hpp"
#include "job/ensemble_spec.hpp"
#include "sampling/design.hpp"

namespace {

using namespace treedyn;
using namespace treedyn::sampling;
using namespace treedyn::designs;

// Three inputs in two units (0: inputs 0 and 2; 1: input 1), 6 levels.
const std::vector<unsigned> kUnits{0, 1, 0};

TEST(MorrisPoints, EachStepMovesOneUnitByHalfInTheDirectionItSays) {
  const MorrisPoints points(7, 6, kUnits, 2);
  ASSERT_EQ(points.runs_per_trajectory(), 3u);
  for (std::uint64_t t = 0; t < 200; ++t) {
    const std::vector<MorrisStep> steps = points.steps(t);
    ASSERT_EQ(steps.size(), 2u);
    EXPECT_NE(steps[0].unit, steps[1].unit);  // each unit once
    std::vector<double> before(3), after(3);
    points.point(t * 3, before);
    for (std::uint64_t s = 1; s < 3; ++s) {
      points.point(t * 3 + s, after);
      for (unsigned d = 0; d < 3; ++d) {
        const double l = after[d] * 6.0 - 0.5;  // the level: an integer 0 .. 5, up to (l + 1/2) / 6's rounding
        EXPECT_NEAR(l, std::round(l), 1e-14);
        EXPECT_GE(l, 0.0);
        EXPECT_LE(l, 5.0);
        const double moved = kUnits[d] == steps[s - 1].unit ? steps[s - 1].direction * kMorrisDelta : 0.0;
        EXPECT_NEAR(after[d] - before[d], moved, 1e-15) << "trajectory " << t << " step " << s << " input " << d;
      }
      before = after;
    }
  }
}

// A pure function of (seed, run): the same bits in any order, and another
// seed gives other points.
TEST(MorrisPoints, RunIsAPureFunctionOfSeedAndIndex) {
  const MorrisPoints a(3, 4, {0, 1, 2}, 3), b(3, 4, {0, 1, 2}, 3), other(4, 4, {0, 1, 2}, 3);
  std::vector<double> x(3), y(3), z(3);
  bool differs = false;
  for (std::uint64_t k = 0; k < 400; ++k) {
    a.point(k, x);
    b.point(399 - k, y);  // b in the other order
    b.point(k, y);
    other.point(k, z);
    EXPECT_EQ(x, y);
    differs = differs || x != z;
  }
  EXPECT_TRUE(differs);
}

// Each input's level is uniform over the p levels: over 6000 trajectories'
// first runs each of 4 levels holds 1500 +- 4 sd (sd = sqrt(6000 / 4 * 3 / 4)
// = 33.5).
TEST(MorrisPoints, LevelsAreDrawnUniformly) {
  const MorrisPoints points(11, 4, {0, 1}, 2);
  std::vector<int> count(8, 0);
  std::vector<double> u(2);
  for (std::uint64_t t = 0; t < 6000; ++t) {
    points.point(t * 3, u);
    for (unsigned d = 0; d < 2; ++d) ++count[d * 4 + static_cast<int>(u[d] * 4.0)];
  }
  for (int c : count) EXPECT_NEAR(c, 1500, 4 * 33.5);
}

// Radial steps: run s of trajectory t is run 0 with unit s - 1's inputs
// replaced (every one of them, by values in (0, 1)), and nothing else.
TEST(MorrisRadial, EachRunIsTheBaseWithOneUnitFromAnotherPoint) {
  const SampleDesign design(Design::morris, 7, 300, 3, kUnits, MorrisSpec{});
  std::vector<double> base(3), run(3);
  for (std::uint64_t t = 0; t < 100; ++t) {
    design.point(t * 3, base);
    for (std::uint64_t s = 1; s < 3; ++s) {
      design.point(t * 3 + s, run);
      for (unsigned d = 0; d < 3; ++d) {
        EXPECT_GT(run[d], 0.0);
        EXPECT_LT(run[d], 1.0);
        if (kUnits[d] == s - 1)
          EXPECT_NE(run[d], base[d]) << t << " " << s << " " << d;
        else
          EXPECT_EQ(run[d], base[d]) << t << " " << s << " " << d;
      }
    }
  }
}

// The spec and inputs (u) of a morris run: radial steps or trajectories on
// 4 levels.
struct Synthetic {
  EnsembleSpec spec;
  std::vector<std::int32_t> status;
  std::vector<double> inputs;
};

Synthetic synthetic(unsigned inputs, std::vector<SobolUnit> units, std::uint64_t trajectories, std::uint64_t seed,
                    bool radial) {
  Synthetic s;
  s.spec.design = Design::morris;
  s.spec.seed = seed;
  MorrisSpec morris;
  morris.trajectories = trajectories;
  morris.radial = radial;
  s.spec.morris = morris;
  s.spec.sobol_units = std::move(units);
  s.spec.perturbations.resize(inputs);  // scalar parameters: one input each
  const std::uint64_t runs = trajectories * (s.spec.unit_count() + 1u);
  s.spec.runs = runs;
  const SampleDesign design(Design::morris, seed, runs, inputs, s.spec.unit_of_input(), s.spec.morris);
  s.status.assign(runs, 0);
  s.inputs.resize(runs * inputs);
  for (std::uint64_t k = 0; k < runs; ++k) design.point(k, std::span<double>(s.inputs).subspan(k * inputs, inputs));
  return s;
}

MorrisIndices indices_of(const Synthetic& s, const std::vector<double>& f, unsigned inputs) {
  const ensemble::ResponseTable table(s.status, s.inputs, f, inputs, 1);
  return morris_indices(elementary_effects(s.spec, table, 0), s.spec.unit_count(), 200, s.spec.seed);
}

// f = sum c_i x_i, x_i = a_i + (b_i - a_i) u_i: each step changes f by
// c_i (b_i - a_i) Delta, so EE_i = c_i (b_i - a_i) in every trajectory.
// Tolerance: a few ulps of the largest term (the differences of sums of
// about 10^2).
class MorrisIndicesBoth : public ::testing::TestWithParam<bool> {};  // radial, trajectories

TEST_P(MorrisIndicesBoth, LinearResponseEffectsAreItsCoefficientsExactly) {
  const std::vector<double> c{3.0, -2.0, 0.5, 0.0}, a{0.0, 1.0, -4.0, 2.0}, b{1.0, 3.0, 4.0, 5.0};
  const unsigned d = 4;
  const Synthetic s = synthetic(d, {{"x0", {0}}, {"x1", {1}}, {"x2", {2}}, {"x3", {3}}}, 25, 5, GetParam());
  std::vector<double> f(s.status.size());
  for (std::size_t k = 0; k < f.size(); ++k)
    for (unsigned i = 0; i < d; ++i) f[k] += c[i] * (a[i] + (b[i] - a[i]) * s.inputs[k * d + i]);
  const MorrisIndices m = indices_of(s, f, d);
  for (unsigned i = 0; i < d; ++i) {
    const double exact = c[i] * (b[i] - a[i]);
    EXPECT_NEAR(m.mu[i], exact, 1e-12) << i;
    EXPECT_NEAR(m.mu_star[i], std::abs(exact), 1e-12) << i;
    EXPECT_NEAR(m.sigma[i], 0.0, 1e-12) << i;
    EXPECT_EQ(m.effects[i], 25u);
  }
  // mu* = 3, 4, 4, 0: x3 (no effect) last, x0 third.
  EXPECT_EQ(m.ranking.order[2], 0u);
  EXPECT_EQ(m.ranking.order[3], 3u);
}

// A trajectory's group moves its inputs together, the same way, by Delta:
// its effect is the sum.
TEST(MorrisIndices, GroupEffectIsTheSumOfItsInputsEffects) {
  const unsigned d = 3;
  const Synthetic s = synthetic(d, {{"x0 and x2", {0, 2}}, {"x1", {1}}}, 20, 9, false);
  std::vector<double> f(s.status.size());
  for (std::size_t k = 0; k < f.size(); ++k) f[k] = 2.0 * s.inputs[k * d] + 5.0 * s.inputs[k * d + 2];
  const MorrisIndices m = indices_of(s, f, d);
  EXPECT_NEAR(m.mu[0], 7.0, 1e-12);
  EXPECT_NEAR(m.sigma[0], 0.0, 1e-12);
  EXPECT_EQ(m.mu[1], 0.0);
  EXPECT_EQ(m.mu_star[1], 0.0);
}

// Sobol's g function on [0, 1]^5, g = prod (|4 u_i - 2| + a_i) / (1 + a_i),
// a = (0, 1, 4.5, 9, 99): the total indices fall with a_i (Saltelli et al.
// 2008, 4.5: 0.79, 0.24, 0.034, 0.010, 0.0001 for the first four and
// a = 99), and so must mu*, each neighbour told apart with 400 trajectories.
TEST_P(MorrisIndicesBoth, GFunctionRankedAsItsTotalIndices) {
  const std::vector<double> a{0.0, 1.0, 4.5, 9.0, 99.0};
  const unsigned d = 5;
  std::vector<SobolUnit> units;
  for (unsigned i = 0; i < d; ++i) units.push_back({"x" + std::to_string(i), {i}});
  const Synthetic s = synthetic(d, units, 400, 21, GetParam());
  std::vector<double> f(s.status.size(), 1.0);
  for (std::size_t k = 0; k < f.size(); ++k)
    for (unsigned i = 0; i < d; ++i) f[k] *= (std::abs(4.0 * s.inputs[k * d + i] - 2.0) + a[i]) / (1.0 + a[i]);
  const MorrisIndices m = indices_of(s, f, d);
  EXPECT_EQ(m.ranking.order, (std::vector<std::size_t>{0, 1, 2, 3, 4}));
  for (std::size_t k = 0; k + 1 < d; ++k) EXPECT_TRUE(m.ranking.told_apart(k)) << "pair " << k;
  for (unsigned i = 0; i < d; ++i) {
    EXPECT_LE(m.mu_star_ci[2 * i], m.mu_star[i]);
    EXPECT_GE(m.mu_star_ci[2 * i + 1], m.mu_star[i]);
  }
}

// A failed run (or a NaN value) takes out the effects of the steps it
// is an end of.
TEST_P(MorrisIndicesBoth, FailedRunDropsTheEffectsOfItsSteps) {
  const unsigned d = 3;
  Synthetic s = synthetic(d, {{"x0", {0}}, {"x1", {1}}, {"x2", {2}}}, 10, 4, GetParam());
  std::vector<double> f(s.status.size());
  for (std::size_t k = 0; k < f.size(); ++k) f[k] = s.inputs[k * d] + s.inputs[k * d + 1] + s.inputs[k * d + 2];
  s.status[1] = 1;  // trajectory 0's run 1: two steps in a trajectory, one radial step
  s.status[4] = 1;  // trajectory 1's run 0: one step in a trajectory, every radial step
  const MorrisIndices m = indices_of(s, f, d);
  const std::uint64_t kept = std::accumulate(m.effects.begin(), m.effects.end(), std::uint64_t{0});
  EXPECT_EQ(kept, GetParam() ? 10u * 3u - 1u - 3u : 10u * 3u - 2u - 1u);
  for (unsigned i = 0; i < d; ++i) EXPECT_NEAR(m.mu[i], 1.0, 1e-12);
}

// A response of period 1/2 in u (Ishigami's sin^2 x on [-pi, pi], a wave's
// phase as sin^2): a trajectory's step of 1/2 cannot see it (every effect
// exactly 0, the documented blind spot), radial steps to an independent
// point do.
TEST(MorrisIndices, RadialStepsSeeWhatHalfStepsMiss) {
  const unsigned d = 2;
  std::vector<double> mu_star;
  for (bool radial : {false, true}) {
    const Synthetic s = synthetic(d, {{"phase", {0}}, {"x", {1}}}, 50, 3, radial);
    std::vector<double> f(s.status.size());
    for (std::size_t k = 0; k < f.size(); ++k) {
      const double phase = std::sin(2.0 * std::numbers::pi * s.inputs[k * d]);
      f[k] = phase * phase + 0.1 * s.inputs[k * d + 1];
    }
    const MorrisIndices m = indices_of(s, f, d);
    mu_star.push_back(m.mu_star[0]);
    if (radial) {
      EXPECT_EQ(m.ranking.order.front(), 0u);
    } else {
      EXPECT_NEAR(m.mu_star[0], 0.0, 1e-12);
    }
  }
  EXPECT_GT(mu_star[1], 1.0);  // |change| about 0.5 over a step of about 1/3
}

INSTANTIATE_TEST_SUITE_P(Variants, MorrisIndicesBoth, ::testing::Values(true, false),
                         [](const ::testing::TestParamInfo<bool>& variant) {
                           return variant.param ? "Radial" : "Trajectories";
                         });

}  // namespace
