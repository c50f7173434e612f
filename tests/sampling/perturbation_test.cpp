// Perturbations (src/sampling/perturbation.*, targets.cpp) and the
// [ensemble] reader (read_ensemble.cpp):
//
//  * every target resolves to the named parameter entries (or to the part of
//    the initial state) it names, and applying a value changes exactly those,
//    bit for bit, with every other entry unchanged;
//  * the derived model follows: a solid's inertia is recomputed from its
//    perturbed mass, density or dimensions, a chain link's joint points move
//    with its length, an explicit-inertia body's mass changes the mass only;
//  * a sample whose perturbed parameters are unphysical is recorded with
//    status 2 and the reason;
//  * bad [ensemble] input is refused with a JobError naming the field.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include "common/error.hpp"
#include "ensemble/sample_runner.hpp"
#include "job/ensemble_spec.hpp"
#include "job/job.hpp"
#include "job/job_error.hpp"
#include "model/definition.hpp"

namespace {

using namespace treedyn;
using namespace treedyn::sampling;

const char* kTargetsJob = R"(title = "perturbation targets"

[environment]
gravity = [0.1, -0.2, -9.81]

[base]
type = "harmonic"
offset = [0.0, 0.0, 0.1]
x = [{ amplitude = 0.01, frequency = 2.0 }]
z = [{ amplitude = 0.02, frequency = 5.0, phase = 30, unit = "deg" }, { amplitude = 0.005, frequency = 11.0 }]

[[body]]
name = "upper"
shape = "box"
size = [0.1, 0.2, 1.0]
mass = 2.0
parent = "base"
joint_on_child = [0.0, 0.0, 0.5]
orientation = { type = "bryant123", angles = [10, 20, 30], unit = "deg" }
angular_velocity = { value = [0.1, 0.2, 0.3], frame = "inertial" }
spring = { stiffness = 3.0, damping = 0.1 }

[[body]]
name = "lower"
shape = "cylinder"
radius = 0.05
length = 0.8
mass = 1.0
parent = "upper"
joint_on_parent = [0.01, 0.02, -0.5]
joint_on_child = [0.0, 0.0, 0.4]
orientation = { type = "axis_angle", axis = [0, 1, 0], angle = 90, unit = "deg" }
angular_velocity = { value = [0.4, 0.5, 0.6], frame = "inertial" }
spring = { stiffness = [[3.0, 0.1, 0.0], [0.1, 4.0, 0.0], [0.0, 0.0, 5.0]], damping = 0.2 }

[output]
end_time = 0.1
step = 0.05

[ensemble]
samples = 4

[[ensemble.perturbation]]
target = "body.lower.mass"
distribution = "uniform"
lower = 0.5
upper = 1.5

[[ensemble.perturbation]]
target = "body.lower.mass"
distribution = "normal"
std = 0.1
mode = "add"

[[ensemble.perturbation]]
target = "body.lower.mass"
distribution = "lognormal"
sigma = 0.1
mode = "scale"

[[ensemble.perturbation]]
target = "body.upper.inertia_scale"
distribution = "uniform"
lower = 0.9
upper = 1.1

[[ensemble.perturbation]]
target = "body.lower.joint_on_child.z"
distribution = "normal"
std = 0.01
mode = "add"

[[ensemble.perturbation]]
target = "body.lower.joint_on_parent.x"
distribution = "normal"
mean = 0.01
std = 0.001

[[ensemble.perturbation]]
target = "body.upper.orientation"
distribution = "normal"
std = 2.0
unit = "deg"

[[ensemble.perturbation]]
target = "body.lower.rotation.z"
distribution = "normal"
std = 0.1
unit = "rad"

[[ensemble.perturbation]]
target = "body.lower.angular_velocity.y"
distribution = "normal"
std = 10.0
unit = "deg/s"
mode = "add"

[[ensemble.perturbation]]
target = "joint.lower.stiffness"
distribution = "uniform"
lower = 0.5
upper = 2.0
mode = "scale"

[[ensemble.perturbation]]
target = "joint.lower.damping"
distribution = "uniform"
lower = 0.0
upper = 0.1
mode = "add"

[[ensemble.perturbation]]
target = "joint.upper.stiffness"
distribution = "uniform"
lower = 1.0
upper = 5.0

[[ensemble.perturbation]]
target = "base.z[2].amplitude"
distribution = "uniform"
lower = 0.5
upper = 1.5
mode = "scale"

[[ensemble.perturbation]]
target = "base.z[1].frequency"
distribution = "normal"
std = 0.5
mode = "add"

[[ensemble.perturbation]]
target = "base.x[1].phase"
distribution = "uniform"
lower = 0.0
upper = 360.0
unit = "deg"

[[ensemble.perturbation]]
target = "gravity.z"
distribution = "normal"
mean = -9.81
std = 0.01

[[ensemble.perturbation]]
target = "gravity.x"
distribution = "normal"
std = 0.01
mode = "add"
)";

// Index of entry `component` of the parameter called `name`.
int index_of(const ParameterTable& table, const std::string& name, int component = 0) {
  const Parameter* p = table.find(name);
  if (!p) {
    ADD_FAILURE() << "no parameter " << name;
    return 0;
  }
  return p->offset + component;
}

void expect_same_state(const InitialState& a, const InitialState& b, const std::string& what) {
  ASSERT_EQ(a.rotation.size(), b.rotation.size());
  for (std::size_t i = 0; i < a.rotation.size(); ++i) {
    EXPECT_TRUE(a.rotation[i] == b.rotation[i]) << what << ": rotation of body " << i;
    EXPECT_TRUE(a.angular_velocity[i] == b.angular_velocity[i]) << what << ": angular velocity " << i;
  }
}

// Rodrigues' formula, written independently of Eigen's AngleAxis.
Mat3 rodrigues(const Vec3& v) {
  const double angle = v.norm();
  const Vec3 a = v / angle;
  Mat3 k;
  k << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return Mat3::Identity() + std::sin(angle) * k + (1.0 - std::cos(angle)) * k * k;
}

// The reader resolves every target to the named entries (or state), mode and
// unit; apply() with a chosen value changes exactly those entries (every
// other entry of the parameter vector, and the initial state, compared
// bitwise unchanged). The expected new values are computed by hand; exact
// except the rotations, which are also checked against Rodrigues' formula to
// 1e-14 (rounding of a few trigonometric products).
TEST(Perturbation, ChangesExactlyItsEntries) {
  const Job job = parse_job(kTargetsJob, "targets.toml");
  const EnsembleSpec spec = read_ensemble(job);
  ASSERT_EQ(spec.perturbations.size(), 17u);
  EXPECT_EQ(spec.input_dimensions(), 19u);  // orientation takes 3
  const ParameterTable& table = job.definition.parameters;
  const std::vector<double> p0(table.nominal().begin(), table.nominal().end());
  const InitialState& s0 = job.initial;
  ASSERT_EQ(job.model.tree().user_body_name(0), "upper");
  ASSERT_EQ(job.model.tree().user_body_name(1), "lower");
  const double deg = std::numbers::pi / 180.0;
  using K = sampling::Perturbation::Kind;
  using M = sampling::Perturbation::Mode;
  auto at = [&](const std::string& name, int component = 0) { return index_of(table, name, component); };

  struct Case {
    K kind;
    std::string entry;  // the first entry's name (parameters) or "" (state)
    int entries;
    int body;  // user index (state)
    int axis;
    M mode;
    double unit;
    std::vector<double> values;
    std::function<void(std::vector<double>&, InitialState&)> expect;
  };
  // clang-format off
  const std::vector<Case> cases = {
      {K::parameter, "body.lower.mass", 1, 0, 0, M::set, 1.0, {1.3},
       [&](std::vector<double>& p, InitialState&) { p[at("body.lower.mass")] = 1.3; }},
      {K::parameter, "body.lower.mass", 1, 0, 0, M::add, 1.0, {0.25},
       [&](std::vector<double>& p, InitialState&) { p[at("body.lower.mass")] = 1.0 + 0.25; }},
      {K::parameter, "body.lower.mass", 1, 0, 0, M::scale, 1.0, {1.5},
       [&](std::vector<double>& p, InitialState&) { p[at("body.lower.mass")] = 1.5; }},
      {K::parameter, "body.upper.inertia_scale", 1, 0, 0, M::set, 1.0, {1.1},
       [&](std::vector<double>& p, InitialState&) { p[at("body.upper.inertia_scale")] = 1.1; }},
      {K::parameter, "body.lower.joint_on_child.z", 1, 0, 0, M::add, 1.0, {0.01},
       [&](std::vector<double>& p, InitialState&) { p[at("body.lower.joint_on_child", 2)] = 0.4 + 0.01; }},
      {K::parameter, "body.lower.joint_on_parent.x", 1, 0, 0, M::set, 1.0, {-0.03},
       [&](std::vector<double>& p, InitialState&) { p[at("body.lower.joint_on_parent", 0)] = -0.03; }},
      {K::orientation, "", 1, 0, 0, M::set, deg, {0.01, -0.02, 0.03},
       [](std::vector<double>&, InitialState& s) {
         const Vec3 v(0.01, -0.02, 0.03);
         s.rotation[0] = Eigen::AngleAxisd(v.norm(), v / v.norm()).toRotationMatrix() * s.rotation[0];
       }},
      {K::rotation, "", 1, 1, 2, M::set, 1.0, {0.2},
       [](std::vector<double>&, InitialState& s) {
         s.rotation[1] = Eigen::AngleAxisd(0.2, Vec3::UnitZ()).toRotationMatrix() * s.rotation[1];
       }},
      {K::angular_velocity, "", 1, 1, 1, M::add, deg, {0.1},
       [](std::vector<double>&, InitialState& s) { s.angular_velocity[1].y() += 0.1; }},
      {K::parameter, "joint.lower.stiffness.xx", 9, 0, 0, M::scale, 1.0, {2.0},
       [&](std::vector<double>& p, InitialState&) {
         const double k[9] = {3.0, 0.1, 0.0, 0.1, 4.0, 0.0, 0.0, 0.0, 5.0};
         for (int e = 0; e < 9; ++e) p[at("joint.lower.stiffness", e)] = k[e] * 2.0;
       }},
      {K::parameter, "joint.lower.damping.xx", 9, 0, 0, M::add, 1.0, {0.05},
       [&](std::vector<double>& p, InitialState&) {
         for (int e : {0, 4, 8}) p[at("joint.lower.damping", e)] = 0.2 + 0.05;
       }},
      {K::parameter, "joint.upper.stiffness.xx", 9, 0, 0, M::set, 1.0, {4.0},
       [&](std::vector<double>& p, InitialState&) {
         for (int e = 0; e < 9; ++e) p[at("joint.upper.stiffness", e)] = e % 4 == 0 ? 4.0 : 0.0;
       }},
      {K::parameter, "base.z[2].amplitude", 1, 0, 0, M::scale, 1.0, {1.2},
       [&](std::vector<double>& p, InitialState&) { p[at("base.z[2].amplitude")] = 0.005 * 1.2; }},
      {K::parameter, "base.z[1].frequency", 1, 0, 0, M::add, 1.0, {0.5},
       [&](std::vector<double>& p, InitialState&) { p[at("base.z[1].frequency")] = 5.5; }},
      {K::parameter, "base.x[1].phase", 1, 0, 0, M::set, deg, {1.0},
       [&](std::vector<double>& p, InitialState&) { p[at("base.x[1].phase")] = 1.0; }},
      {K::parameter, "gravity.z", 1, 0, 0, M::set, 1.0, {-9.7},
       [&](std::vector<double>& p, InitialState&) { p[at("gravity", 2)] = -9.7; }},
      {K::parameter, "gravity.x", 1, 0, 0, M::add, 1.0, {0.02},
       [&](std::vector<double>& p, InitialState&) { p[at("gravity", 0)] = 0.1 + 0.02; }},
  };
  // clang-format on
  ASSERT_EQ(cases.size(), spec.perturbations.size());
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const sampling::Perturbation& p = spec.perturbations[i];
    const Case& c = cases[i];
    const std::string what = "perturbation " + std::to_string(i + 1) + " (" + p.target + ")";
    EXPECT_EQ(p.kind, c.kind) << what;
    if (c.kind == K::parameter) {
      EXPECT_EQ(table.entry_name(p.first), c.entry) << what;
      EXPECT_EQ(p.entries, c.entries) << what;
    } else {
      EXPECT_EQ(p.first, c.body) << what;
      EXPECT_EQ(p.axis, c.axis) << what;
    }
    EXPECT_EQ(p.mode, c.mode) << what;
    EXPECT_EQ(p.unit, c.unit) << what;
    ASSERT_EQ(static_cast<std::size_t>(p.dimensions()), c.values.size()) << what;

    std::vector<double> params = p0, expected_params = p0;
    InitialState s = s0, expected_s = s0;
    p.apply(c.values, params, s);
    c.expect(expected_params, expected_s);
    for (std::size_t e = 0; e < params.size(); ++e)
      EXPECT_TRUE(std::memcmp(&params[e], &expected_params[e], sizeof(double)) == 0)
          << what << ": entry " << table.entry_name(static_cast<int>(e)) << " is " << params[e] << ", expected "
          << expected_params[e];
    expect_same_state(s, expected_s, what);
  }

  // Rotations, independently: R' R^T is the rotation by the vector.
  {
    std::vector<double> params = p0;
    InitialState s = s0;
    const Vec3 v(0.01, -0.02, 0.03);
    spec.perturbations[6].apply(std::vector<double>{v.x(), v.y(), v.z()}, params, s);
    EXPECT_LT((s.rotation[0] * s0.rotation[0].transpose() - rodrigues(v)).norm(), 1e-14);
    spec.perturbations[7].apply(std::vector<double>{0.2}, params, s);
    EXPECT_LT((s.rotation[1] * s0.rotation[1].transpose() - rodrigues(Vec3(0, 0, 0.2))).norm(), 1e-14);
    // A zero rotation vector changes nothing.
    InitialState z = s0;
    spec.perturbations[6].apply(std::vector<double>{0.0, 0.0, 0.0}, params, z);
    EXPECT_TRUE(z.rotation[0] == s0.rotation[0]);
  }

  // sample(): quantile times unit. u = 0.5 of a uniform [0, 360] deg phase
  // is pi rad (exact up to one rounding); of normal(-9.81, 0.01) it is -9.81.
  {
    double out = 0.0;
    const double half = 0.5;
    spec.perturbations[14].sample(std::span<const double>(&half, 1), std::span<double>(&out, 1));
    EXPECT_NEAR(out, std::numbers::pi, 1e-15);
    spec.perturbations[15].sample(std::span<const double>(&half, 1), std::span<double>(&out, 1));
    EXPECT_NEAR(out, -9.81, 1e-14);
    std::vector<double> three(3);
    const std::vector<double> us = {0.5, 0.5, 0.5};
    spec.perturbations[6].sample(us, three);
    EXPECT_EQ(three, std::vector<double>(3, 0.0));
  }
}

// A one-rod job plus the given text: its [ensemble] (and a [base], which
// TOML lets stand after [output]; without one the base is fixed).
std::string rod_job(const std::string& ensemble) {
  return R"([[body]]
name = "rod"
shape = "cylinder"
radius = 0.02
length = 1.0
mass = 1.0
parent = "base"
joint_on_child = [0.0, 0.0, 0.5]

[output]
end_time = 0.1
step = 0.05

)" + ensemble;
}

// base.acceleration.AXIS on a constant_acceleration base.
TEST(Perturbation, BaseAcceleration) {
  const std::string text = rod_job(R"([base]
type = "constant_acceleration"
acceleration = [0.5, 0.0, 1.0]

[ensemble]
samples = 2

[[ensemble.perturbation]]
target = "base.acceleration.z"
distribution = "normal"
std = 0.1
mode = "add"
)");
  const Job job = parse_job(text, "accel.toml");
  const EnsembleSpec spec = read_ensemble(job);
  ASSERT_EQ(spec.perturbations.size(), 1u);
  const sampling::Perturbation& p = spec.perturbations[0];
  const ParameterTable& table = job.definition.parameters;
  EXPECT_EQ(table.entry_name(p.first), "base.acceleration.z");
  std::vector<double> params(table.nominal().begin(), table.nominal().end());
  InitialState s = job.initial;
  p.apply(std::vector<double>{0.25}, params, s);
  EXPECT_EQ(params[index_of(table, "base.acceleration", 2)], 1.25);
  Model model;
  derive_model(job.definition, params, model);
  EXPECT_EQ(model.base_motion.at(2.0).acceleration, Vec3(0.5, 0.0, 1.25));
}

// A sea state's targets: Hs and Tp are scalars, the phases a list whose
// entries are inputs one by one (uniform on [0, 2 pi) without a
// distribution); the derived base motion is the sea state with exactly
// those values: against the sum of sines of components() of the axis built
// by hand (same frequencies, amplitudes scaled by Hs, phases as set).
TEST(Perturbation, SeaStateHeightPeriodAndPhases) {
  const std::string text = rod_job(R"([base]
type = "sea_state"
phase_seed = 5

[base.z]
significant_height = 2.0
peak_period = 8.0
components = 6

[ensemble]
samples = 4

[[ensemble.perturbation]]
target = "base.z.significant_height"
distribution = "uniform"
lower = 1.0
upper = 3.0

[[ensemble.perturbation]]
target = "base.z.phases"
)");
  const Job job = parse_job(text, "sea.toml");
  const EnsembleSpec spec = read_ensemble(job);
  ASSERT_EQ(spec.perturbations.size(), 2u);
  EXPECT_EQ(spec.input_dimensions(), 7u);
  const std::vector<std::string> names = spec.input_names();
  EXPECT_EQ(names[1], "base.z.phases[1]");
  EXPECT_EQ(names[6], "base.z.phases[6]");
  const sampling::Perturbation& phases = spec.perturbations[1];
  EXPECT_EQ(phases.kind, sampling::Perturbation::Kind::parameter_list);
  EXPECT_EQ(phases.distribution.kind, sampling::Distribution::Kind::uniform);
  EXPECT_EQ(phases.distribution.upper, 2.0 * std::numbers::pi);
  const ParameterTable& table = job.definition.parameters;
  EXPECT_EQ(table.entry_name(phases.first + 5), "base.z.phases[6]");

  std::vector<double> params(table.nominal().begin(), table.nominal().end());
  const std::vector<double> nominal_params = params;
  InitialState s = job.initial;
  const std::vector<double> values = {2.5, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6};
  sampling::apply_inputs(spec.perturbations, values, job.initial, params, s);
  for (std::size_t k = 0; k < params.size(); ++k) {
    const int i = static_cast<int>(k);
    if (i == index_of(table, "base.z.significant_height"))
      EXPECT_EQ(params[k], 2.5);
    else if (i >= phases.first && i < phases.first + 6)
      EXPECT_EQ(params[k], values[k - phases.first + 1]);
    else
      EXPECT_EQ(params[k], nominal_params[k]) << table.entry_name(i);
  }
  Model model;
  derive_model(job.definition, params, model);
  SeaStateAxis by_hand = *std::get<SeaStateBase>(job.definition.base.kind).axes[2];
  const SeaStateAxis nominal = by_hand;
  by_hand.significant_height = 2.5;
  by_hand.phases = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6};
  const std::vector<SeaComponent> c = components(by_hand), c0 = components(nominal);
  for (double t : {0.0, 0.37, 5.0}) {
    double z = 0.0;
    for (const SeaComponent& k : c) z += k.amplitude * std::sin(2.0 * std::numbers::pi * k.frequency * t + k.phase);
    // BaseMotion sums the components by a complex recurrence (a few ulp per
    // component, model/base_motion.hpp): 1e-13 of a ~0.5 m motion.
    EXPECT_NEAR(model.base_motion.at(t).position.z(), z, 1e-13) << t;
  }
  for (std::size_t k = 0; k < c.size(); ++k) {
    EXPECT_EQ(c[k].frequency, c0[k].frequency);  // the grid stays the job's
    EXPECT_NEAR(c[k].amplitude, 1.25 * c0[k].amplitude, 1e-15);
  }
  EXPECT_EQ(phases.mode, sampling::Perturbation::Mode::set);

  // With a distribution a list needs its mode said, and is never scaled; without
  // one, no distribution field may stand alone.
  const std::string phase_entry = "[[ensemble.perturbation]]\ntarget = \"base.z.phases\"\n";
  for (const auto& [extra, field, says] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"distribution = \"normal\"\nstd = 5.0\nunit = \"deg\"\n", "distribution", "say what it does to each phase"},
           {"distribution = \"normal\"\nstd = 0.1\nmode = \"scale\"\n", "mode", "not scaled"},
           {"std = 0.1\n", "std", "without 'distribution' every entry is uniform on [0, 2 pi)"}}) {
    std::string bad = text;
    bad.replace(bad.find(phase_entry), phase_entry.size(), phase_entry + extra);
    try {
      read_ensemble(parse_job(bad, "sea.toml"));
      ADD_FAILURE() << "accepted:\n" << extra;
    } catch (const JobError& e) {
      EXPECT_EQ(e.field(), "ensemble.perturbation[2]." + field) << e.what();
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  }
}

// read_ensemble refuses bad input with a JobError naming the field.

struct Refusal {
  std::string name;
  std::string ensemble;           // the [ensemble] text
  std::string field;              // JobError::field()
  std::vector<std::string> says;  // substrings of what()
};

// Each case: read_ensemble throws JobError, its field() is exactly the
// offending key's dotted path, and what() holds the listed words (what was
// wrong and what is allowed). Where the key exists in the file the line
// number is the key's line.
TEST(ReadEnsemble, RefusesBadInput) {
  const std::string p = "[ensemble]\nsamples = 8\n\n[[ensemble.perturbation]]\n";
  // clang-format off
  const std::vector<Refusal> cases = {
      {"unknown target", p + "target = \"body.rod.colour\"\ndistribution = \"normal\"\nstd = 1.0\n",
       "ensemble.perturbation[1].target", {"'body.rod.colour' is not a target", "allowed targets"}},
      {"unknown body", p + "target = \"body.arm.mass\"\ndistribution = \"normal\"\nstd = 1.0\n",
       "ensemble.perturbation[1].target", {"'arm' is not a body of the model"}},
      {"bad axis", p + "target = \"gravity.w\"\ndistribution = \"normal\"\nstd = 1.0\n",
       "ensemble.perturbation[1].target", {"axis 'w'", "x, y or z"}},
      {"harmonic target on a fixed base",
       p + "target = \"base.z[1].amplitude\"\ndistribution = \"normal\"\nstd = 1.0\n",
       "ensemble.perturbation[1].target", {"harmonic"}},
      {"bad distribution", p + "target = \"body.rod.mass\"\ndistribution = \"gaussian\"\nstd = 1.0\n",
       "ensemble.perturbation[1].distribution", {"\"gaussian\" is not allowed", "\"normal\"", "\"lognormal\""}},
      {"missing std", p + "target = \"body.rod.mass\"\ndistribution = \"normal\"\nmean = 1.0\n",
       "ensemble.perturbation[1].std", {"missing required field"}},
      {"std not positive", p + "target = \"body.rod.mass\"\ndistribution = \"normal\"\nstd = 0.0\n",
       "ensemble.perturbation[1].std", {"must be > 0"}},
      {"uniform lower > upper",
       p + "target = \"body.rod.mass\"\ndistribution = \"uniform\"\nlower = 2.0\nupper = 1.0\n",
       "ensemble.perturbation[1].upper", {"greater than 'lower'"}},
      {"uniform lower == upper",
       p + "target = \"body.rod.mass\"\ndistribution = \"uniform\"\nlower = 1.0\nupper = 1.0\n",
       "ensemble.perturbation[1].upper", {"greater than 'lower'"}},
      {"truncated lower >= upper",
       p + "target = \"body.rod.mass\"\ndistribution = \"truncated_normal\"\nmean = 1.0\nstd = 0.1\n"
           "lower = 1.2\nupper = 0.8\n",
       "ensemble.perturbation[1].upper", {"greater than 'lower'"}},
      {"truncated interval without probability",
       p + "target = \"body.rod.mass\"\ndistribution = \"truncated_normal\"\nmean = 1.0\nstd = 0.01\n"
           "lower = 2.0\nupper = 3.0\n",
       "ensemble.perturbation[1].lower", {"no probability"}},
      {"angle without unit", p + "target = \"body.rod.rotation.x\"\ndistribution = \"normal\"\nstd = 1.0\n",
       "ensemble.perturbation[1].unit", {"\"deg\"", "\"rad\""}},
      {"unit on an SI target",
       p + "target = \"body.rod.mass\"\ndistribution = \"normal\"\nstd = 1.0\nunit = \"g\"\n",
       "ensemble.perturbation[1].unit", {"SI"}},
      {"unit on a scale factor",
       p + "target = \"body.rod.angular_velocity.z\"\ndistribution = \"uniform\"\nlower = 0.99\n"
           "upper = 1.01\nmode = \"scale\"\nunit = \"deg/s\"\n",
       "ensemble.perturbation[1].unit", {"dimensionless"}},
      {"unknown key with suggestion",
       p + "target = \"body.rod.mass\"\ndistribution = \"normal\"\nstdev = 1.0\n",
       "ensemble.perturbation[1].stdev", {"unknown key 'stdev'", "did you mean 'std'?"}},
      {"unknown [ensemble] key with suggestion", "[ensemble]\nsample = 8\n", "ensemble.sample",
       {"unknown key 'sample'", "did you mean 'samples'?"}},
      {"bad mode", p + "target = \"body.rod.mass\"\ndistribution = \"normal\"\nstd = 1.0\nmode = \"mul\"\n",
       "ensemble.perturbation[1].mode", {"\"mul\" is not allowed"}},
      {"mode on a rotation",
       p + "target = \"body.rod.rotation.x\"\ndistribution = \"normal\"\nstd = 1.0\nunit = \"deg\"\n"
           "mode = \"add\"\n",
       "ensemble.perturbation[1].mode", {"not used for this target"}},
      {"missing samples", "[ensemble]\nseed = 3\n", "ensemble.samples", {"missing required field"}},
      {"zero samples", "[ensemble]\nsamples = 0\n", "ensemble.samples", {"at least 1"}},
      {"bad design", "[ensemble]\nsamples = 8\ndesign = \"halton\"\n", "ensemble.design",
       {"\"halton\" is not allowed", "\"sobol\""}},
      {"quantile outside (0, 1)", "[ensemble]\nsamples = 8\nquantiles = [0.5, 1.0]\n", "ensemble.quantiles",
       {"(0, 1)"}},
      {"missing [ensemble]", "", "ensemble", {"missing [ensemble] section"}},
  };
  // clang-format on
  for (const Refusal& c : cases) {
    const std::string text = rod_job(c.ensemble);
    const Job job = parse_job(text, "bad.toml");
    try {
      read_ensemble(job);
      ADD_FAILURE() << c.name << ": accepted";
    } catch (const JobError& e) {
      std::printf("%-40s %s\n", c.name.c_str(), e.what());
      EXPECT_EQ(e.field(), c.field) << c.name << ": " << e.what();
      for (const std::string& s : c.says)
        EXPECT_NE(std::string(e.what()).find(s), std::string::npos) << c.name << ": '" << s << "' not in: " << e.what();
      EXPECT_EQ(e.file(), "bad.toml");
      // The line of the offending key, where it is in the file.
      const std::string key = c.field.substr(c.field.rfind('.') + 1);
      const std::size_t at = text.find("\n" + key + " = ");
      if (at != std::string::npos && text.find("\n" + key + " = ", at + 1) == std::string::npos) {
        const int line = 2 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
        EXPECT_EQ(e.line(), line) << c.name << ": " << e.what();
      }
    } catch (const std::exception& e) {
      ADD_FAILURE() << c.name << ": not a JobError: " << e.what();
    }
  }
}

// Names that are not targets of this job say why, and what to perturb.
TEST(ReadEnsemble, MissingTargetsSayWhyAndWhatInstead) {
  const std::string model = R"([base]
type = "harmonic"
z = [{ amplitude = 0.01, frequency = 2.0 }]

[[body]]
name = "arm"
mass = 1.0
principal_moments = [0.1, 0.1, 0.05]
parent = "base"
joint_on_child = [0.0, 0.0, 0.3]

[[body]]
name = "crate"
shape = "box"
size = [0.2, 0.2, 0.2]
density = 500.0
parent = "arm"
joint_on_parent = [0.0, 0.0, -0.3]

[[chain]]
name = "link"
links = 3
link_length = 0.2
mass = 0.1
parent = "crate"

[output]
end_time = 0.1
step = 0.05

[ensemble]
samples = 2

[[ensemble.perturbation]]
distribution = "normal"
std = 0.01
)";
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {"body.link2.joint_on_child.z", {"upper end of the cylinder", "body.link2.length"}},
      {"body.link2.joint_on_parent.z", {"lower end of the cylinder 'link1'", "body.link1.length"}},
      {"body.arm.joint_on_parent.x", {"hangs from the base", "[base]"}},
      {"body.arm.density", {"given explicitly", "body.arm.mass", "inertia_scale"}},
      {"body.arm.length", {"no shape", "given explicitly"}},
      {"body.crate.length", {"is a box", "body.crate.size.x"}},
      {"body.crate.inertia", {"homogeneous box", "inertia_scale"}},
      {"gravity", {"is a vector", "gravity.x"}},
      {"gravity.w", {"axis 'w'", "x, y or z"}},
      // Targets of kinds other jobs have: which base this one has and what
      // it offers instead, or that it has no [[force]].
      {"base.acceleration.z", {"whose [base] is harmonic", "; its base targets: base.offset.AXIS, base.z[1]."}},
      {"base.position.x", {"whose [base] is harmonic", "mean position is base.offset.AXIS", "; its base targets"}},
      {"base.z[2].amplitude", {"K counts from 1", "base.z[1].amplitude"}},
      {"force[1].force.x", {"it has no [[force]]; add one"}},
      {"moment[2].moment.z", {"it has no [[moment]]"}},
      {"joint.hand.stiffness", {"'hand' is not a body", "named by its child"}},
      {"body.arm.colour", {"is not a target", "allowed targets for body 'arm'", "body.arm.mass"}},
      {"spring.arm", {"is not a target", "treedyn check --parameters"}},
  };
  for (const auto& [target, says] : cases) {
    const Job job = parse_job(model + "target = \"" + target + "\"\n", "missing.toml");
    try {
      read_ensemble(job);
      ADD_FAILURE() << target << ": accepted";
    } catch (const JobError& e) {
      EXPECT_EQ(e.field(), "ensemble.perturbation[1].target") << target;
      for (const std::string& s : says)
        EXPECT_NE(std::string(e.what()).find(s), std::string::npos) << target << ": '" << s << "' not in " << e.what();
    }
  }
  // ... while the ones that exist resolve, including the mass of a solid
  // given by its density (through the density, at the nominal volume).
  for (const std::string target : {"body.crate.mass", "body.crate.size.y", "body.link2.length",
                                   "body.link1.joint_on_parent.x", "base.z[1].phase", "base.offset.z"}) {
    const Job job =
        parse_job(model + "target = \"" + target + "\"\n" + (target == "base.z[1].phase" ? "unit = \"rad\"\n" : ""),
                  "exists.toml");
    EXPECT_NO_THROW(read_ensemble(job)) << target;
  }
  const Job job = parse_job(model + "target = \"body.crate.mass\"\nmode = \"set\"\n", "mass.toml");
  const EnsembleSpec spec = read_ensemble(job);
  std::vector<double> params(job.definition.parameters.nominal().begin(), job.definition.parameters.nominal().end());
  InitialState state = job.initial;
  spec.perturbations[0].apply(std::vector<double>{6.0}, params, state);
  Model m;
  derive_model(job.definition, params, m);
  const int crate = job.model.tree().regular_index[1];
  EXPECT_NEAR(m.mass[crate], 6.0, 1e-15 * 6.0);  // (6 / V) x V: one rounding each way
  EXPECT_NEAR(m.inertia[crate](0, 0), 6.0 * (0.04 + 0.04) / 12.0, 1e-15);
}

}  // namespace
