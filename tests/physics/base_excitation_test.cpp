// Prescribed base motion r0(t) and joint spring-dampers: the equivalence of
// base acceleration and gravity, the energy balance E(t) - E(0) = base work -
// damper losses (docs/wittenburg.md, section 6), tabulated vs analytic base motion, and energy
// conservation with springs on a fixed base.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "dynamics/recovered.hpp"
#include "integrate/simulate.hpp"
#include "model/model.hpp"
#include "support/random_tree.hpp"

namespace treedyn {
namespace {

struct Trajectory {
  IntegrationOutcome outcome;
  std::vector<Recovered> out;  // one per output time
};

Trajectory run(const ModelSpec& spec, const InitialState& initial, const std::vector<double>& times, double rtol,
               double atol, Parameterisation p = Parameterisation::quaternion) {
  const Model model = build_model(spec);
  SimulationRequest request;
  request.parameterisation = p;
  request.settings.method = Method::cvode_adams;
  request.settings.relative_tolerance = rtol;
  request.settings.absolute_tolerance = atol;
  request.output_times = times;
  Trajectory r;
  r.out.reserve(times.size());
  r.outcome =
      simulate(model, initial, request, [&](const Model& m, const Data& data) { r.out.push_back(recover(m, data)); });
  return r;
}

std::vector<double> grid(double duration, int intervals) {
  std::vector<double> t;
  for (int k = 0; k <= intervals; ++k) t.push_back(duration * k / intervals);
  return t;
}

int body_index(const ModelSpec& spec, const std::string& name) {
  for (std::size_t i = 0; i < spec.bodies.size(); ++i)
    if (spec.bodies[i].name == name) return static_cast<int>(i);
  ADD_FAILURE() << "no body " << name;
  return -1;
}

// The energy that moves around at the start (energies can pass through zero).
double energy_scale(const Energies& e) { return e.kinetic + std::abs(e.potential) + e.spring; }

// ---------------------------------------------------------------------------
// Base acceleration == extra gravity.

// r0'' enters the equations only as M b_i0 x (r0'' - g) (section 4), so a
// base moving as r0 = p + v t + a t^2/2 under gravity g gives the same
// rotations as a fixed base at p under gravity g - a, and every body point is
// displaced by exactly v t + a t^2/2 (velocities by v + a t). The two runs
// differ only by rounding in the force terms (and hence in the step
// sequence), so their difference is far below each run's own error.
// This random tree is chaotic: runs at rtol 1e-12 and 1e-13 differ by 4e-9
// rad at 2 s and 1e-6 rad at 5 s, and the rounding-level difference between
// the two formulations grows alike (measured 7e-12 at 2 s, 4e-11 at 3 s, 2e-9
// at 5 s). Over 3 s the tolerances 1e-9 rad for rotations, 1e-9 m for
// positions (lever arms < 1.5 m) and 1e-8 m/s, rad/s for velocities keep a
// margin of ~20; a missing or mis-signed r0'' term would be O(1).
TEST(BaseExcitation, ConstantAccelerationIsExtraGravity) {
  std::mt19937_64 rng(4242);
  testing::RandomTreeOptions options;
  options.bodies = 4;
  const ModelSpec tree = testing::random_tree(rng, options);
  const InitialState initial = testing::random_state(rng, options.bodies, 3.0);
  const double g = 9.81;
  struct Case {
    const char* what;
    Vec3 velocity;
    Vec3 acceleration;
  };
  const std::vector<Case> cases = {
      {"upward a = 3 m/s^2 from rest", Vec3::Zero(), Vec3(0.0, 0.0, 3.0)},
      {"oblique a, initial base velocity", Vec3(0.4, 0.3, -0.2), Vec3(1.5, -2.0, 3.0)},
  };
  const Vec3 p0(0.1, -0.2, 0.3);
  const std::vector<double> times = grid(3.0, 150);
  for (const Case& c : cases) {
    ModelSpec fixed = tree;
    fixed.gravity = Vec3(0.0, 0.0, -g) - c.acceleration;
    fixed.base_motion = FixedBase{p0};
    ModelSpec moving = tree;
    moving.gravity = Vec3(0.0, 0.0, -g);
    moving.base_motion = ConstantAccelerationBase{p0, c.velocity, c.acceleration};

    const Trajectory a = run(fixed, initial, times, 1e-12, 1e-12);
    const Trajectory b = run(moving, initial, times, 1e-12, 1e-12);
    ASSERT_TRUE(a.outcome.ok()) << a.outcome.message;
    ASSERT_TRUE(b.outcome.ok()) << b.outcome.message;
    ASSERT_EQ(a.out.size(), times.size());
    ASSERT_EQ(b.out.size(), times.size());
    double rot = 0.0, w = 0.0, pos = 0.0, vel = 0.0, joint = 0.0;
    for (std::size_t k = 0; k < times.size(); ++k) {
      const double t = times[k];
      const Vec3 shift = c.velocity * t + 0.5 * c.acceleration * t * t;
      const Vec3 shift_rate = c.velocity + c.acceleration * t;
      // The base itself.
      pos = std::max(pos, (b.out[k].base.position - a.out[k].base.position - shift).norm());
      for (int i = 0; i < options.bodies; ++i) {
        const auto u = static_cast<std::size_t>(i);
        rot = std::max(rot, testing::rotation_distance(a.out[k].rotation[u], b.out[k].rotation[u]));
        w = std::max(w, (a.out[k].angular_velocity[u] - b.out[k].angular_velocity[u]).norm());
        pos = std::max(pos, (b.out[k].com_position[u] - a.out[k].com_position[u] - shift).norm());
        vel = std::max(vel, (b.out[k].com_velocity[u] - a.out[k].com_velocity[u] - shift_rate).norm());
        joint = std::max(joint, (b.out[k].joint_position[u] - a.out[k].joint_position[u] - shift).norm());
      }
    }
    std::printf(
        "%-34s rotation %.2e rad  |w| %.2e rad/s  CoM position %.2e m  joint position %.2e m  "
        "CoM velocity %.2e m/s\n",
        c.what, rot, w, pos, joint, vel);
    EXPECT_LT(rot, 1e-9) << c.what;
    EXPECT_LT(w, 1e-8) << c.what;
    EXPECT_LT(pos, 1e-9) << c.what;
    EXPECT_LT(joint, 1e-9) << c.what;
    EXPECT_LT(vel, 1e-8) << c.what;
  }
}

// ---------------------------------------------------------------------------
// Energy balance under harmonic base motion with springs and dampers.

HarmonicBase two_axis_shaker() {
  HarmonicBase h;
  h.offset = Vec3(0.05, 0.0, 0.2);
  h.axes[0] = {Harmonic{0.02, 3.0, 0.0}, Harmonic{0.004, 7.0, 1.1}};  // x: 3 Hz + a 7 Hz overtone
  h.axes[2] = {Harmonic{0.03, 2.0, 0.4}};                             // z: 2 Hz
  return h;
}

ModelSpec damped_sprung_tree(std::mt19937_64& rng) {
  testing::RandomTreeOptions options;
  options.bodies = 3;
  options.spring_stiffness = 2.0;  // N m / rad
  options.spring_damping = 0.05;   // N m s / rad
  ModelSpec spec = testing::random_tree(rng, options);
  // Make one damper anisotropic and one spring reference non-trivial, so the
  // child-frame convention of the law is exercised.
  const Mat3 R = testing::random_rotation(rng);
  spec.joints[1].spring.damping = R * Vec3(0.02, 0.06, 0.1).asDiagonal() * R.transpose();
  spec.joints[2].spring.reference = Quat(testing::random_rotation(rng));
  spec.base_motion = two_axis_shaker();
  return spec;
}

// Powers at one output: base work rate X_1 . r0' through the joint on the
// base, and damper dissipation sum_a w_rel . D_a w_rel, with w_rel = A_c^T
// (w_c - w_p) in the child's frame (the law of JointSpring), computed here
// from recovered rotations and angular velocities only.
struct Powers {
  double base = 0.0;
  double damper = 0.0;
};

Powers powers(const ModelSpec& spec, const Recovered& r) {
  Powers p;
  for (const JointSpec& j : spec.joints) {
    const auto c = static_cast<std::size_t>(body_index(spec, j.child));
    const bool on_base = j.parent == kBaseName;
    const Vec3 w_parent =
        on_base ? Vec3::Zero() : r.angular_velocity[static_cast<std::size_t>(body_index(spec, j.parent))];
    const Vec3 w_rel = r.rotation[c].transpose() * (r.angular_velocity[c] - w_parent);
    p.damper += w_rel.dot(j.spring.damping * w_rel);
    if (on_base) p.base += r.joint_reaction[c].dot(r.base.velocity);
  }
  return p;
}

// E(t) - E(0) = integral of X_1 . r0' - integral of damper power (section 6,
// absolute-frame energy including the springs' 2 e^T K e).
// The integrals are composite Simpson on a 0.5 ms output grid (dense output
// of an rtol = atol = 1e-12 Adams run). Simpson's error is at most
// T h^4/180 max|P''''|. The fastest content of the base power is at 14 Hz
// (the 7 Hz overtone's velocity 0.18 m/s times its reaction ~3 kg x 7.7
// m/s^2: ~2 W), so |P''''| <~ 88^4 x 2 W ~ 1.2e8 W/s^4 and the bound is
// 4 s x 6.25e-14 s^4 x 1.2e8 / 180 ~ 1.7e-7 J, i.e. 6e-9 of the ~27 J energy
// scale (the body motion is far slower). The integration's own error is
// ~1e-11 relative (the spring test below). Tolerance: 2e-8 of the energy
// scale; the base work (~3 J) and damper loss (~15 J) are 8-9 orders larger,
// so any slip in X_1, r0', the base terms or the damper law would show.
void expect_work_balances_energy(const ModelSpec& spec, const InitialState& initial) {
  const double duration = 4.0;
  const int intervals = 8000;  // 0.5 ms, even, for Simpson
  const std::vector<double> times = grid(duration, intervals);
  const Trajectory r = run(spec, initial, times, 1e-12, 1e-12);
  ASSERT_TRUE(r.outcome.ok()) << r.outcome.message;
  ASSERT_EQ(r.out.size(), times.size());

  std::vector<Powers> P;
  for (const Recovered& x : r.out) P.push_back(powers(spec, x));
  const double h = duration / intervals;
  const double E0 = r.out[0].energy.total();
  const double scale = energy_scale(r.out[0].energy);
  double W_base = 0.0, W_damper = 0.0, worst = 0.0, worst_t = 0.0, max_work = 0.0, max_change = 0.0;
  for (int k = 2; k <= intervals; k += 2) {
    const auto i = static_cast<std::size_t>(k);
    W_base += h / 3.0 * (P[i - 2].base + 4.0 * P[i - 1].base + P[i].base);
    W_damper += h / 3.0 * (P[i - 2].damper + 4.0 * P[i - 1].damper + P[i].damper);
    const double change = r.out[i].energy.total() - E0;
    const double err = std::abs(change - (W_base - W_damper));
    if (err > worst) {
      worst = err;
      worst_t = times[i];
    }
    max_work = std::max(max_work, std::abs(W_base));
    max_change = std::max(max_change, std::abs(change));
  }
  std::printf(
      "energy scale %.3f J; max |E - E0| %.3f J; max |base work| %.3f J; damper loss %.3f J "
      "at the end;\nworst |E - E0 - (W_base - W_damper)| %.2e J = %.2e of scale (t = %.3f s); "
      "steps %ld\n",
      scale, max_change, max_work, W_damper, worst, worst / scale, worst_t, r.outcome.stats.steps);
  // Not vacuous: the base does work and the dampers take some.
  EXPECT_GT(max_work, 0.05 * scale);
  EXPECT_GT(W_damper, 1e-3 * scale);
  EXPECT_LT(worst / scale, 2e-8);
}

TEST(BaseExcitation, HarmonicWorkBalancesEnergy) {
  std::mt19937_64 rng(9090);
  const ModelSpec spec = damped_sprung_tree(rng);
  expect_work_balances_energy(spec, testing::random_state(rng, 3, 3.0));
}

// The same balance under a sea state (model/sea_state.hpp): 64 JONSWAP
// components of a "sea" at shaker scale (Hs 0.1 m, Tp 1 s: components from
// 0.5 to 3.5 Hz, the fastest power content at 7 Hz, within the 14 Hz the
// Simpson bound above allows), along x and z, one of them through an RAO.
TEST(BaseExcitation, SeaStateWorkBalancesEnergy) {
  std::mt19937_64 rng(9090);
  ModelSpec spec = damped_sprung_tree(rng);
  SeaStateBase sea;
  sea.offset = Vec3(0.05, 0.0, 0.2);
  std::uniform_real_distribution<double> phase(0.0, 2.0 * std::numbers::pi);
  for (int axis : {0, 2}) {
    SeaStateAxis a;
    a.significant_height = 0.1;
    a.peak_period = 1.0;
    a.min_frequency = 0.5;
    a.max_frequency = 3.5;
    for (int k = 0; k < 64; ++k) a.phases.push_back(phase(rng));
    if (axis == 2) a.rao = {{0.0, 2.0, 4.0}, {1.0, 0.6, 0.2}, {0.0, 0.5, 1.5}};
    sea.axes[axis] = a;
  }
  spec.base_motion = sea;
  expect_work_balances_energy(spec, testing::random_state(rng, 3, 3.0));
}

// ---------------------------------------------------------------------------
// Tabulated base motion.

TabulatedBase tabulate(const BaseMotion& exact, double t0, double t1, double dt) {
  TabulatedBase tab;
  const int n = static_cast<int>(std::lround((t1 - t0) / dt));
  for (int k = 0; k <= n; ++k) {
    const double t = t0 + k * dt;
    tab.times.push_back(t);
    tab.positions.push_back(exact.at(t).position);
  }
  return tab;
}

// A natural cubic spline through 1 ms samples of the harmonic shaker, with the
// table extending 0.2 s (200 knots) beyond [0, 4] so the natural end
// conditions' error (decaying by 2 - sqrt 3 per knot) is gone inside.
// Interpolation bounds (Hall & Meyer) with h = 1e-3 and |f''''| <= sum A w^4
// = 1.75e4 m/s^4 (x: 0.02 x 18.85^4 + 0.004 x 43.98^4; z adds 750 in
// quadrature): position 5/384 h^4 |f''''| = 2.3e-10 m, velocity h^3/24
// |f''''| = 7.3e-7 m/s, acceleration 3/8 h^2 |f''''| = 6.6e-3 m/s^2. These
// are the tolerances (2.4e-10, 7.5e-7, 7e-3). Knots are interpolated exactly.
// Continuity: across each interior knot at +-1e-10 s the jumps are bounded
// by the next derivative times 2e-10 s (|v| < 1 m/s, |a| < 20 m/s^2, spline
// jerk ~|f'''| < 550 m/s^3 -> 2e-10, 4e-9, 1.1e-7); we ask 5e-10 m, 1e-8
// m/s, 2e-7 m/s^2. A C1-only spline would jump by ~0.5 m/s^2 in
// acceleration, a C0 one by ~5e-4 m/s in velocity. (Near the table's ends
// the natural end condition r0'' = 0 forces a jerk up to |f''|/h ~ 2e4 m/s^3,
// decaying by 2 - sqrt 3 per knot inwards, so the jumps are checked on the
// knots in [0, 4], 200 knots from the ends; the ends are checked through the
// end values.)
// Outside the table: linear continuation (r0'' = 0, constant r0'), continuous
// at the ends.
TEST(BaseExcitation, TabulatedBaseIsAccurateAndContinuous) {
  const BaseMotion exact(two_axis_shaker());
  const TabulatedBase tab = tabulate(exact, -0.2, 4.2, 1e-3);
  const BaseMotion spline(tab);
  EXPECT_FALSE(spline.is_fixed());

  double knot = 0.0;
  for (std::size_t k = 0; k < tab.times.size(); ++k)
    knot = std::max(knot, (spline.at(tab.times[k]).position - tab.positions[k]).norm());

  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> when(0.0, 4.0);
  double ep = 0.0, ev = 0.0, ea = 0.0;
  for (int k = 0; k < 20000; ++k) {
    const double t = when(rng);
    const BaseKinematics s = spline.at(t), e = exact.at(t);
    ep = std::max(ep, (s.position - e.position).norm());
    ev = std::max(ev, (s.velocity - e.velocity).norm());
    ea = std::max(ea, (s.acceleration - e.acceleration).norm());
  }

  const double d = 1e-10;
  double jp = 0.0, jv = 0.0, ja = 0.0;
  auto jump = [&](double t) {
    const BaseKinematics l = spline.at(t - d), r = spline.at(t + d);
    jp = std::max(jp, (r.position - l.position).norm());
    jv = std::max(jv, (r.velocity - l.velocity).norm());
    ja = std::max(ja, (r.acceleration - l.acceleration).norm());
  };
  for (double t : tab.times)
    if (t >= 0.0 && t <= 4.0) jump(t);
  const double jp_in = jp, jv_in = jv, ja_in = ja;
  // Across the table's ends, from the spline into the straight continuation.
  jp = jv = ja = 0.0;
  jump(tab.times.front());
  jump(tab.times.back());

  // Beyond the ends: straight lines with the end velocities.
  const BaseKinematics end = spline.at(tab.times.back()), start = spline.at(tab.times.front());
  const BaseKinematics after = spline.at(tab.times.back() + 1.0), before = spline.at(tab.times.front() - 1.0);
  const double outside =
      std::max({(after.position - end.position - end.velocity).norm(), (after.velocity - end.velocity).norm(),
                after.acceleration.norm(), (before.position - start.position + start.velocity).norm(),
                (before.velocity - start.velocity).norm(), before.acceleration.norm(), end.acceleration.norm(),
                start.acceleration.norm()});

  std::printf(
      "knots %.2e m; off-knot errors: position %.2e m, velocity %.2e m/s, acceleration %.2e "
      "m/s^2;\njumps at knots +-1e-10 s: %.2e m, %.2e m/s, %.2e m/s^2; at the table's ends %.2e m, "
      "%.2e m/s, %.2e m/s^2; outside the table %.2e\n",
      knot, ep, ev, ea, jp_in, jv_in, ja_in, jp, jv, ja, outside);
  EXPECT_LT(knot, 1e-15);
  EXPECT_LT(ep, 2.4e-10);
  EXPECT_LT(ev, 7.5e-7);
  EXPECT_LT(ea, 7e-3);
  EXPECT_LT(jp_in, 5e-10);
  EXPECT_LT(jv_in, 1e-8);
  EXPECT_LT(ja_in, 2e-7);
  // At the ends the spline's jerk is up to |f''|/h ~ 2e4 m/s^3: 4e-6 m/s^2.
  EXPECT_LT(jp, 5e-10);
  EXPECT_LT(jv, 1e-8);
  EXPECT_LT(ja, 1e-5);
  EXPECT_LT(outside, 1e-12);
}

// The same damped, sprung tree on the analytic shaker and on its 1 ms table:
// the only difference is the base acceleration error (<= 1.5e-3 m/s^2, mostly
// far less, oscillating at the knot rate and averaging out), acting on arms
// < 1 m for 4 s, so the states differ by well under 1e-4 (rad, rad/s, m, m/s)
// unless the tabulated base is fed in wrongly (e.g. a wrong time argument or
// velocity). Tolerance 1e-4 as briefed; the numbers reached are printed.
TEST(BaseExcitation, TabulatedBaseReproducesHarmonicRun) {
  std::mt19937_64 rng(9090);
  const ModelSpec harmonic = damped_sprung_tree(rng);
  const InitialState initial = testing::random_state(rng, 3, 3.0);
  ModelSpec tabulated = harmonic;
  tabulated.base_motion = tabulate(BaseMotion(two_axis_shaker()), -0.2, 4.2, 1e-3);
  const std::vector<double> times = grid(4.0, 400);
  const Trajectory a = run(harmonic, initial, times, 1e-11, 1e-11);
  const Trajectory b = run(tabulated, initial, times, 1e-11, 1e-11);
  ASSERT_TRUE(a.outcome.ok()) << a.outcome.message;
  ASSERT_TRUE(b.outcome.ok()) << b.outcome.message;
  ASSERT_EQ(a.out.size(), times.size());
  ASSERT_EQ(b.out.size(), times.size());
  double rot = 0.0, w = 0.0, pos = 0.0, vel = 0.0;
  for (std::size_t k = 0; k < times.size(); ++k) {
    for (std::size_t u = 0; u < 3; ++u) {
      rot = std::max(rot, testing::rotation_distance(a.out[k].rotation[u], b.out[k].rotation[u]));
      w = std::max(w, (a.out[k].angular_velocity[u] - b.out[k].angular_velocity[u]).norm());
      pos = std::max(pos, (a.out[k].com_position[u] - b.out[k].com_position[u]).norm());
      vel = std::max(vel, (a.out[k].com_velocity[u] - b.out[k].com_velocity[u]).norm());
    }
  }
  std::printf(
      "tabulated vs harmonic: rotation %.2e rad  |w| %.2e rad/s  position %.2e m  velocity %.2e m/s  "
      "(steps %ld vs %ld)\n",
      rot, w, pos, vel, b.outcome.stats.steps, a.outcome.stats.steps);
  EXPECT_LT(rot, 1e-4);
  EXPECT_LT(w, 1e-4);
  EXPECT_LT(pos, 1e-4);
  EXPECT_LT(vel, 1e-4);
}

// ---------------------------------------------------------------------------
// Springs on a fixed base conserve T + V + spring energy.

// Random trees of 1-5 bodies with joint springs (no dampers), spinning at up
// to 4 rad/s so the joints swing through large relative rotations. Every
// other tree gets anisotropic stiffness K = R diag(k) R^T and a random
// reference orientation. The law V = 2 e^T K e with moment -2 (q0 K e +
// (K e) x e) is conservative for any symmetric K, so at rtol = atol = 1e-12
// the drift over 20 s is integration error, ~1e-10 relative (the conservation
// test sees the same without springs). Tolerance 1e-8 of the energy scale.
TEST(BaseExcitation, SpringsConserveEnergyOnFixedBase) {
  std::mt19937_64 rng(5150);
  const std::vector<double> times = grid(20.0, 200);
  for (int n = 1; n <= 5; ++n) {
    testing::RandomTreeOptions options;
    options.bodies = n;
    options.spring_stiffness = 3.0;
    ModelSpec spec = testing::random_tree(rng, options);
    const bool anisotropic = n % 2 == 0;
    if (anisotropic) {
      std::uniform_real_distribution<double> k(0.5, 5.0);
      for (JointSpec& j : spec.joints) {
        const Mat3 R = testing::random_rotation(rng);
        j.spring.stiffness = R * Vec3(k(rng), k(rng), k(rng)).asDiagonal() * R.transpose();
        j.spring.reference = Quat(testing::random_rotation(rng));
      }
    }
    const InitialState initial = testing::random_state(rng, n, 4.0);
    const Trajectory r = run(spec, initial, times, 1e-12, 1e-12);
    ASSERT_TRUE(r.outcome.ok()) << r.outcome.message;
    ASSERT_EQ(r.out.size(), times.size());
    const double scale = energy_scale(r.out[0].energy);
    double drift = 0.0, max_spring = 0.0;
    for (const Recovered& x : r.out) {
      drift = std::max(drift, std::abs(x.energy.total() - r.out[0].energy.total()) / scale);
      max_spring = std::max(max_spring, x.energy.spring);
    }
    std::printf("n=%d %-11s energy drift %.2e of %.3f J  (max spring energy %.3f J)  steps %ld\n", n,
                anisotropic ? "anisotropic" : "isotropic", drift, scale, max_spring, r.outcome.stats.steps);
    EXPECT_GT(max_spring, 1e-3 * scale) << "n = " << n << ": springs barely loaded";
    EXPECT_LT(drift, 1e-8) << "n = " << n;
  }
}

}  // namespace
}  // namespace treedyn
