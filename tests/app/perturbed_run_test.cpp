// A perturbed ensemble sample is the job with the sampled value written in.
// treedyn-ensemble (one rank) perturbs one input of a two-body pendulum, or
// of a chain; for every sample, `treedyn run` of the same job with the
// sampled value written into the file (as a shape's mass, density or length,
// or as the explicit joint points a chain link's length implies) must reach
// the same final orientations and angular velocities, to 1e-12. This is what
// "a solid stays homogeneous" means: its inertia (and a chain link's joints)
// follow the perturbed value exactly as they follow a written one.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "support/command.hpp"
#include "support/hdf5_reader.hpp"

namespace {

using namespace treedyn::testing;
namespace fs = std::filesystem;

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", v);
  return buffer;
}

// "@NAME@" replaced by `value` everywhere in `text`.
std::string with(std::string text, const std::string& name, const std::string& value) {
  const std::string key = "@" + name + "@";
  for (auto at = text.find(key); at != std::string::npos; at = text.find(key, at + value.size()))
    text.replace(at, key.size(), value);
  return text;
}

// What every job here integrates and records: 2 s, tight tolerances, the
// final state's quantities.
const std::string kSettings = R"(
[integrator]
rtol = 1e-10
atol = 1e-12

[output]
end_time = 2.0
step = 0.05
quantities = ["orientation", "angular_velocity"]
)";

// A rod (a cylinder given by mass) with a ball (a sphere given by density)
// on its end, released tilted and spinning, for 2 s.
const std::string kPendulum = R"(
[[body]]
name = "rod"
shape = "cylinder"
radius = 0.02
length = @length@
mass = @mass@
parent = "base"
joint_on_child = [0.0, 0.0, 0.5]
orientation = { type = "axis_angle", axis = [1, 0, 0], angle = 40, unit = "deg" }
angular_velocity = { value = [0.0, 0.0, 1.5], frame = "inertial" }

[[body]]
name = "ball"
shape = "sphere"
radius = 0.05
density = @density@
parent = "rod"
joint_on_parent = [0.0, 0.0, -0.5]
joint_on_child = [0.0, 0.0, 0.05]

)" + kSettings;

// Three links, given as a [[chain]] (joints at their ends, moving with their
// lengths) ...
const std::string kChain = R"(
[[chain]]
name = "c"
links = 3
link_length = 0.4
radius = 0.01
mass = 0.3
orientation = { type = "axis_angle", axis = [1, 1, 0], angle = 50, unit = "deg" }
angular_velocity = { value = [0.0, 0.0, 2.0], frame = "inertial" }

)" + kSettings;

// ... and written out as bodies with explicit joint points.
std::string explicit_chain(double length2) {
  const double L[3] = {0.4, length2, 0.4};
  std::string text;
  const char* parent[3] = {"base", "c1", "c2"};
  for (int k = 0; k < 3; ++k) {
    text += "[[body]]\nname = \"c" + std::to_string(k + 1) +
            "\"\nshape = \"cylinder\"\nradius = 0.01\nmass = 0.3\nlength = " + number(L[k]) + "\nparent = \"" +
            parent[k] + "\"\njoint_on_child = [0.0, 0.0, " + number(0.5 * L[k]) + "]\n";
    if (k > 0) text += "joint_on_parent = [0.0, 0.0, " + number(-0.5 * L[k - 1]) + "]\n";
    text +=
        "orientation = { type = \"axis_angle\", axis = [1, 1, 0], angle = 50, unit = \"deg\" }\n"
        "angular_velocity = { value = [0.0, 0.0, 2.0], frame = \"inertial\" }\n\n";
  }
  return text + kSettings;
}

std::string ensemble_section(const std::string& target, double lower, double upper, const std::string& extra = "") {
  return "\n[ensemble]\nsamples = 6\nseed = 4\ndesign = \"latin_hypercube\"\npilot_samples = 2\n\n"
         "[[ensemble.perturbation]]\ntarget = \"" +
         target +
         "\"\ndistribution = \"uniform\"\n"
         "lower = " +
         number(lower) + "\nupper = " + number(upper) + "\n" + extra;
}

struct Case {
  std::string target;
  double lower, upper;
  // The job text with the sampled value written in.
  std::string (*rerun)(double value);
  std::string ensemble_job;  // without [ensemble]
  std::string extra = "";    // more keys of the perturbation (a unit)
};

std::string pendulum(double length, double mass, double density) {
  return with(with(with(kPendulum, "length", number(length)), "mass", number(mass)), "density", number(density));
}

void expect_samples_match_reruns(const Case& c) {
  SCOPED_TRACE(c.target);
  TempDir dir("perturbed_run_test");
  const fs::path job = dir.path() / "ensemble.toml", out = dir.path() / "ensemble.h5";
  write_text(job, c.ensemble_job + ensemble_section(c.target, c.lower, c.upper, c.extra));
  fs::create_directory(dir.path() / "capture");
  const CommandResult e =
      run_command(TREEDYN_ENSEMBLE_BINARY, {job.string(), "-o", out.string(), "-q"}, dir.path() / "capture");
  ASSERT_EQ(e.exit_code, 0) << e.err;
  H5File f(out);
  const std::vector<double> inputs = read_doubles(f.id(), "/samples/inputs");
  const std::vector<double> finals = read_doubles(f.id(), "/samples/final_state");
  const std::vector<long long> status = read_integers(f.id(), "/samples/status");
  ASSERT_EQ(inputs.size(), 6u);
  const std::size_t per_sample = finals.size() / 6;
  double worst = 0.0;
  for (std::size_t k = 0; k < 6; ++k) {
    ASSERT_EQ(status[k], 0) << "sample " << k;
    const fs::path rerun = dir.path() / ("rerun" + std::to_string(k) + ".toml");
    const fs::path rerun_out = dir.path() / ("rerun" + std::to_string(k) + ".h5");
    write_text(rerun, c.rerun(inputs[k]));
    const CommandResult r =
        run_command(TREEDYN_BINARY, {"run", rerun.string(), "-o", rerun_out.string(), "-q"}, dir.path() / "capture");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    H5File g(rerun_out);
    const DoubleArray q = read_double_array(g.id(), "/orientation");
    const DoubleArray w = read_double_array(g.id(), "/angular_velocity");
    const std::size_t bodies = per_sample / 7;
    const std::size_t last_q = q.data.size() - 4 * bodies, last_w = w.data.size() - 3 * bodies;
    for (std::size_t b = 0; b < bodies; ++b) {
      for (std::size_t i = 0; i < 4; ++i)
        worst = std::max(worst, std::abs(finals[k * per_sample + 7 * b + i] - q.data[last_q + 4 * b + i]));
      for (std::size_t i = 0; i < 3; ++i)
        worst = std::max(worst, std::abs(finals[k * per_sample + 7 * b + 4 + i] - w.data[last_w + 3 * b + i]));
    }
  }
  std::printf("%-20s largest difference of a final-state component over 6 samples: %.3g\n", c.target.c_str(), worst);
  EXPECT_LE(worst, 1e-12);
}

TEST(PerturbedRun, ShapeMassEqualsTheMassWrittenIn) {
  expect_samples_match_reruns(
      {"body.rod.mass", 0.5, 2.0, [](double v) { return pendulum(1.0, v, 7800.0); }, pendulum(1.0, 1.0, 7800.0)});
}

TEST(PerturbedRun, ShapeLengthEqualsTheLengthWrittenIn) {
  expect_samples_match_reruns(
      {"body.rod.length", 0.6, 1.4, [](double v) { return pendulum(v, 1.0, 7800.0); }, pendulum(1.0, 1.0, 7800.0)});
}

TEST(PerturbedRun, ShapeDensityEqualsTheDensityWrittenIn) {
  expect_samples_match_reruns({"body.ball.density", 2000.0, 9000.0, [](double v) { return pendulum(1.0, 1.0, v); },
                               pendulum(1.0, 1.0, 7800.0)});
}

// The mass of a solid the job gives by density: the sample sets the density
// to mass x (1 / nominal volume), as docs/jobs.md says; the rerun writes that
// density (the ball's volume computed as model/solids.cpp does). Its mass is
// then the sampled one to a rounding (parameters_test checks 1e-15).
TEST(PerturbedRun, MassOfASolidGivenByDensityEqualsItsDensityWrittenIn) {
  expect_samples_match_reruns({"body.ball.mass", 2.0, 6.0,
                               [](double v) {
                                 const double volume = 4.0 / 3.0 * std::numbers::pi * 0.05 * 0.05 * 0.05;
                                 return pendulum(1.0, 1.0, v * (1.0 / volume));
                               },
                               pendulum(1.0, 1.0, 7800.0)});
}

// The pendulum with its rod's joints given as `upper` and `lower`.
std::string with_ends(double length, const std::string& upper, const std::string& lower) {
  std::string t = pendulum(length, 1.0, 7800.0);
  const std::string child = "joint_on_child = [0.0, 0.0, 0.5]", parent = "joint_on_parent = [0.0, 0.0, -0.5]";
  t.replace(t.find(child), child.size(), "joint_on_child = " + upper);
  t.replace(t.find(parent), parent.size(), "joint_on_parent = " + lower);
  return t;
}

// "upper_end" and "lower_end" follow the rod's length: the same as the job
// with both ends written out for that length.
TEST(PerturbedRun, CylinderEndsFollowTheLength) {
  expect_samples_match_reruns({"body.rod.length", 0.6, 1.4,
                               [](double v) {
                                 return with_ends(v, "[0.0, 0.0, " + number(0.5 * v) + "]",
                                                  "[0.0, 0.0, " + number(-0.5 * v) + "]");
                               },
                               with_ends(1.0, "\"upper_end\"", "\"lower_end\"")});
}

// The bodies listed child first (the file's order is not the tree's order):
// a parameter and an initial-state target of the child still land on it.
std::string shuffled(const std::string& text) {
  const std::size_t rod = text.find("[[body]]"), ball = text.find("[[body]]", rod + 1);
  const std::size_t end = text.find("[integrator]");
  return text.substr(0, rod) + text.substr(ball, end - ball) + text.substr(rod, ball - rod) + text.substr(end);
}

TEST(PerturbedRun, ShuffledBodyOrder) {
  expect_samples_match_reruns({"body.ball.density", 2000.0, 9000.0,
                               [](double v) { return shuffled(pendulum(1.0, 1.0, v)); },
                               shuffled(pendulum(1.0, 1.0, 7800.0))});
  expect_samples_match_reruns(
      {"body.ball.rotation.x", 0.1, 0.5,
       [](double v) {
         std::string t = shuffled(pendulum(1.0, 1.0, 7800.0));
         const std::string at = "joint_on_child = [0.0, 0.0, 0.05]\n";
         return t.replace(t.find(at), at.size(),
                          at + "orientation = { type = \"axis_angle\", axis = [1, 0, 0], angle = " + number(v) +
                              ", unit = \"rad\" }\n");
       },
       shuffled(pendulum(1.0, 1.0, 7800.0)), "unit = \"rad\"\n"});
}

TEST(PerturbedRun, ChainLinkLengthMovesItsJoints) {
  expect_samples_match_reruns({"body.c2.length", 0.2, 0.7, [](double v) { return explicit_chain(v); }, kChain});
}

// A length perturbed below zero makes an invalid model: status 2 with the
// reason, the others run; the job succeeds.
TEST(PerturbedRun, UnphysicalSampleIsRecordedWithStatus2) {
  TempDir dir("perturbed_run_test");
  const fs::path job = dir.path() / "ensemble.toml", out = dir.path() / "ensemble.h5";
  write_text(job, pendulum(1.0, 1.0, 7800.0) + ensemble_section("body.rod.length", -0.5, 1.0));
  fs::create_directory(dir.path() / "capture");
  const CommandResult e =
      run_command(TREEDYN_ENSEMBLE_BINARY, {job.string(), "-o", out.string(), "-q"}, dir.path() / "capture");
  ASSERT_EQ(e.exit_code, 0) << e.err;
  H5File f(out);
  const std::vector<double> inputs = read_doubles(f.id(), "/samples/inputs");
  const std::vector<long long> status = read_integers(f.id(), "/samples/status");
  const std::vector<std::string> reason = read_strings(f.id(), "/samples/reason");
  int refused = 0;
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    if (inputs[k] > 0.0) {
      EXPECT_EQ(status[k], 0) << k;
      continue;
    }
    ++refused;
    EXPECT_EQ(status[k], 2) << k;
    EXPECT_NE(reason[k].find("body 'rod': length"), std::string::npos) << reason[k];
    EXPECT_NE(reason[k].find("must be positive"), std::string::npos) << reason[k];
  }
  EXPECT_GE(refused, 1);
}

}  // namespace
