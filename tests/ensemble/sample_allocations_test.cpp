// A sample's heap allocations do not grow with its output times (issue 17:
// recording allocates nothing per output time). The same perturbed rod is
// run with 11 and with 1001 output times, every quantity recorded, through
// SampleRunner::run as a rank runs it, after warm-up runs that size the
// recorder's and the trajectory's storage; the allocations counted during
// one more run must be the same number for both: operator new (the record,
// the recorder) and, where malloc is counted (not under a sanitizer), every
// malloc too (the integrator's set-up, SUNDIALS' own, per sample).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "ensemble/sample_runner.hpp"
#include "job/ensemble_spec.hpp"
#include "job/job.hpp"

#include "support/allocation_counting.inc"

namespace treedyn::ensemble {
namespace {

// A rod on a pivot, every quantity recorded, a tip point, a response.
std::string job_text(const std::string& step) {
  return R"(
[[body]]
name = "rod"
shape = "cylinder"
radius = 0.02
length = 1.0
mass = 1.0
parent = "base"
joint_on_child = [0.0, 0.0, 0.5]
orientation = { type = "axis_angle", axis = [1, 0, 0], angle = 30, unit = "deg" }
angular_velocity = { value = [0.0, 0.0, 2.0], frame = "inertial", unit = "rad/s" }

[output]
end_time = 1.0
step = )" + step + R"(

[[output.point]]
name = "tip"
body = "rod"
point = [0.0, 0.0, -0.5]

[ensemble]
samples = 8
seed = 5

[[ensemble.perturbation]]
target = "body.rod.angular_velocity.z"
distribution = "uniform"
lower = 1.8
upper = 2.2

[[ensemble.response]]
name = "highest_tip"
quantity = "point_position"
column = "tip.z"
reduce = "max"
)";
}

// Allocations during sample 3's run, after two runs of samples 1 and 2.
AllocationCount allocations_of_a_sample(const std::string& step, std::size_t& times) {
  const Job job = parse_job(job_text(step), "rod.toml");
  const EnsembleSpec spec = read_ensemble(job);
  SampleRunner runner(job, spec);
  std::vector<double> trajectory;
  for (std::uint64_t k : {1, 2}) EXPECT_EQ(runner.run(k, false, trajectory).status, SampleStatus::ok);
  const AllocationCount before;
  const SampleRecord r = runner.run(3, false, trajectory);
  const AllocationCount after;
  EXPECT_EQ(r.status, SampleStatus::ok) << r.reason;
  times = runner.times();
  return {after.news - before.news, after.mallocs - before.mallocs};
}

TEST(SampleAllocations, DoNotGrowWithTheOutputTimes) {
  std::size_t few_times = 0, many_times = 0;
  const AllocationCount few = allocations_of_a_sample("0.1", few_times);
  const AllocationCount many = allocations_of_a_sample("0.001", many_times);
  ASSERT_EQ(few_times, 11u);
  ASSERT_EQ(many_times, 1001u);
  EXPECT_GT(few.news, 0) << "the counter counts (a record owns its numbers)";
  EXPECT_EQ(many.news, few.news) << "operator new per sample with 1001 output times against 11";
#if defined(TREEDYN_COUNTS_MALLOC)
  EXPECT_GT(few.mallocs, few.news) << "malloc is counted (SUNDIALS' set-up)";
  EXPECT_EQ(many.mallocs, few.mallocs) << "malloc per sample with 1001 output times against 11";
#endif
}

}  // namespace
}  // namespace treedyn::ensemble
