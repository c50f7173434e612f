// A sample written as a job (--write-job) reads back to the same model and
// initial state, bit for bit, whatever the names hold; jobs it cannot strip
// of their [ensemble] are refused, not written wrong.
#include "job/sample_job.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "ensemble/sample_runner.hpp"
#include "job/ensemble_spec.hpp"
#include "job/job.hpp"
#include "job/job_error.hpp"

namespace {

using namespace treedyn;

// A body whose name needs TOML escapes, an orientation, a mass and a spin.
const std::string kJob = R"(title = "sample job test"

[[body]]
name = "r\"o\\d"
shape = "cylinder"
radius = 0.02
length = 0.5
mass = 1.0
parent = "base"
joint_on_child = [0.0, 0.0, 0.25]
angular_velocity = { value = [0.0, 0.0, 1.0], frame = "body" }

[output]
end_time = 0.1
step = 0.05

# The ensemble: this comment goes with it.
[ensemble]
samples = 5
seed = 3

[[ensemble.perturbation]]
target = "body.r\"o\\d.orientation"
distribution = "normal"
std = 5.0
unit = "deg"

[[ensemble.perturbation]]
target = "body.r\"o\\d.mass"
distribution = "uniform"
lower = 0.5
upper = 2.0
mode = "scale"

[[ensemble.perturbation]]
target = "body.r\"o\\d.angular_velocity.x"
distribution = "normal"
std = 0.3
mode = "add"
)";

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(SampleJob, ReadsBackToTheSampleBitForBit) {
  const Job job = parse_job(kJob, "job.toml");
  const EnsembleSpec spec = read_ensemble(job);
  for (std::uint64_t k = 0; k < spec.runs; ++k) {
    SCOPED_TRACE("sample " + std::to_string(k));
    ensemble::SampleRunner runner(job, spec);
    const std::vector<double> inputs = runner.prepare(k, false);
    const std::string text = sample_job_text(job, spec, k, inputs);
    EXPECT_EQ(text.find("[ensemble"), std::string::npos) << text;
    EXPECT_EQ(text.find("this comment goes with it"), std::string::npos) << text;
    Job again = parse_job(text, "sample.toml");
    apply_sample_section(again);
    ASSERT_EQ(again.model.n, 1);
    EXPECT_TRUE(same_bits(again.model.mass[0], runner.model().mass[0]));
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        EXPECT_TRUE(same_bits(again.model.inertia[0](a, b), runner.model().inertia[0](a, b)));
        EXPECT_TRUE(same_bits(again.initial.rotation[0](a, b), runner.initial_state().rotation[0](a, b)));
      }
    for (int a = 0; a < 3; ++a)
      EXPECT_TRUE(same_bits(again.initial.angular_velocity[0][a], runner.initial_state().angular_velocity[0][a]));
    // The sample differs from the nominal (the test is not vacuous).
    EXPECT_NE(again.model.mass[0], job.model.mass[0]);
    // And a sample job is not written from it again.
    EXPECT_THROW(require_not_a_sample_job(again), JobError);
  }
}

TEST(SampleJob, AnEnsembleWrittenWithoutHeadersIsRefused) {
  // A top-level inline table (it must come before the first table).
  const std::string top =
      "ensemble = { samples = 2, perturbation = [{ target = \"body.r\\\"o\\\\d.mass\", "
      "distribution = \"uniform\", lower = 0.5, upper = 2.0 }] }\n";
  const std::string job_text = top + kJob.substr(0, kJob.find("# The ensemble"));
  const Job job = parse_job(job_text, "inline.toml");
  const EnsembleSpec spec = read_ensemble(job);
  ensemble::SampleRunner runner(job, spec);
  const std::vector<double> inputs = runner.sample_inputs(1);
  try {
    sample_job_text(job, spec, 1, inputs);
    FAIL() << "written";
  } catch (const JobError& e) {
    EXPECT_NE(std::string(e.what()).find("write it with [ensemble] headers"), std::string::npos) << e.what();
  }
}

}  // namespace
