// The probability that a perturbation draws a value the model refuses
// (sampling/invalid_mass.hpp), against closed forms of the normal and
// uniform distributions, for every mode (set, add, scale), a mass given
// through a density, a frequency (>= 0) and a spring matrix (positive
// semi-definite); and against counting: the share of samples that actually
// fail as invalid models in a run of 4000 Monte-Carlo samples.
#include "sampling/invalid_mass.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "common/error.hpp"
#include "ensemble/sample_runner.hpp"
#include "job/ensemble_spec.hpp"
#include "job/job.hpp"

namespace treedyn::sampling {
namespace {

// Standard normal CDF in closed form.
double phi(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

const char* kModel = R"(
[base]
type = "harmonic"
z = [{ amplitude = 0.01, frequency = 50.0 }]

[[body]]
name = "rod"
shape = "cylinder"
radius = 0.02
length = 1.0
mass = 2.0
parent = "base"
joint_on_child = [0.0, 0.0, 0.5]
spring = { stiffness = [[2.0, 0.0, 0.0], [0.0, 4.0, 0.0], [0.0, 0.0, 8.0]] }

[[body]]
name = "bob"
shape = "sphere"
radius = 0.1
density = 1000.0
parent = "rod"
joint_on_parent = [0.0, 0.0, -0.5]

[output]
times = [0.0, 0.01]

[ensemble]
samples = 4000
seed = 11

[[ensemble.perturbation]]
)";

double mass_outside(const std::string& perturbation) {
  const Job job = parse_job(std::string(kModel) + perturbation, "invalid.toml");
  const EnsembleSpec spec = read_ensemble(job);
  const auto m = invalid_mass(spec.perturbations.at(0), job.definition);
  if (!m) throw std::runtime_error("no range for " + perturbation);
  return m->probability;
}

// Closed forms; the CDFs are Boost's, so the tolerance is a few ulps of the
// probability (1e-12 relative).
TEST(InvalidMass, ClosedFormsForEveryMode) {
  struct Case {
    const char* perturbation;
    double expected;
  };
  const Case cases[] = {
      // set: P(m <= 0) for m ~ N(0.5, 0.3^2).
      {"target = \"body.rod.mass\"\ndistribution = \"normal\"\nmean = 0.5\nstd = 0.3\n", phi(-0.5 / 0.3)},
      // set, uniform on [-0.1, 0.9]: a tenth below zero.
      {"target = \"body.rod.mass\"\ndistribution = \"uniform\"\nlower = -0.1\nupper = 0.9\n", 0.1},
      // add to the nominal 2 kg: P(2 + x <= 0), x ~ N(0, 1).
      {"target = \"body.rod.mass\"\nmode = \"add\"\ndistribution = \"normal\"\nstd = 1.0\n", phi(-2.0)},
      // scale: P(2 x <= 0), x ~ N(1, 0.4^2).
      {"target = \"body.rod.mass\"\nmode = \"scale\"\ndistribution = \"normal\"\nmean = 1.0\nstd = 0.4\n", phi(-2.5)},
      // The mass of a solid given by its density: the sign is the same.
      {"target = \"body.bob.mass\"\ndistribution = \"normal\"\nmean = 4.0\nstd = 2.0\n", phi(-2.0)},
      // A frequency may be 0 (>= 0): P(f < 0), f ~ N(50, 20^2).
      {"target = \"base.z[1].frequency\"\ndistribution = \"normal\"\nmean = 50.0\nstd = 20.0\n", phi(-2.5)},
      // A spring matrix scaled: every eigenvalue times x >= 0, x ~ N(1, 0.5^2).
      {"target = \"joint.rod.stiffness\"\nmode = \"scale\"\ndistribution = \"normal\"\nmean = 1.0\nstd = 0.5\n",
       phi(-2.0)},
      // x E added: the smallest eigenvalue (2) plus x >= 0, x ~ N(0, 1).
      {"target = \"joint.rod.stiffness\"\nmode = \"add\"\ndistribution = \"normal\"\nstd = 1.0\n", phi(-2.0)},
      // A lognormal is always positive.
      {"target = \"body.rod.mass\"\ndistribution = \"lognormal\"\nmu = 0.0\nsigma = 1.0\n", 0.0},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.perturbation);
    const double p = mass_outside(c.perturbation);
    EXPECT_NEAR(p, c.expected, 1e-12 * std::max(c.expected, 1e-300) + 1e-300) << p;
  }
}

// Targets without a range have none to report.
TEST(InvalidMass, TargetsWithoutARangeHaveNone) {
  for (const char* target : {"body.rod.orientation", "body.rod.angular_velocity.x", "gravity.z",
                             "body.rod.joint_on_child.z", "base.z[1].amplitude"}) {
    const std::string angle = std::string(target).find("orientation") != std::string::npos ? "unit = \"rad\"\n" : "";
    const Job job =
        parse_job(std::string(kModel) + "target = \"" + target + "\"\ndistribution = \"normal\"\nstd = 0.1\n" + angle,
                  "none.toml");
    EXPECT_FALSE(invalid_mass(read_ensemble(job).perturbations.at(0), job.definition)) << target;
  }
}

// What the model does: 4000 Monte-Carlo samples of m ~ N(0.5, 0.3^2); the
// share refused as invalid models agrees with the CDF within 4 binomial
// standard deviations (p = 0.0478: sd 0.0034).
TEST(InvalidMass, TheShareOfRefusedSamplesIsTheProbability) {
  const Job job =
      parse_job(std::string(kModel) + "target = \"body.rod.mass\"\ndistribution = \"normal\"\nmean = 0.5\nstd = 0.3\n",
                "count.toml");
  const EnsembleSpec spec = read_ensemble(job);
  const double p = invalid_mass(spec.perturbations.at(0), job.definition)->probability;
  ensemble::SampleRunner runner(job, spec);
  std::uint64_t refused = 0;
  for (std::uint64_t k = 0; k < spec.runs; ++k) {
    try {
      runner.prepare(k, false);
    } catch (const ModelError&) {
      ++refused;
    }
  }
  const double n = static_cast<double>(spec.runs), share = static_cast<double>(refused) / n;
  EXPECT_NEAR(share, p, 4.0 * std::sqrt(p * (1.0 - p) / n)) << refused << " of " << spec.runs;
}

}  // namespace
}  // namespace treedyn::sampling
