// A sample's heap allocations do not grow with its output times (issue 17:
// recording allocates nothing per output time). The shipped spherical
// pendulum (every quantity recorded, a body point, three perturbations) is
// run over its 10 s with its own 1001 output times and with every 100th of
// them (11), through SampleRunner::run as a rank runs it, after warm-up
// runs that size the recorder's and the trajectory's storage; the
// allocations counted during one more run must be the same number for
// both: operator new (the record, the recorder) and, where malloc is
// counted (not under a sanitizer), every malloc too (the integrator's
// set-up, SUNDIALS' own, per sample).
#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

#include "ensemble/sample_runner.hpp"
#include "job/job_document.hpp"
#include "job/sample_job.hpp"

#include "support/allocation_counting.inc"

namespace treedyn::ensemble {
namespace {

// Allocations during sample 3's run, after runs of samples 1 and 2, with
// every `every`-th output time of the job.
AllocationCount allocations_of_a_sample(std::size_t every, std::size_t& times) {
  auto [job, spec] = read_ensemble_job(JobDocument::read(TREEDYN_JOBS_DIR "/spherical_pendulum.toml"));
  std::vector<double> kept;
  for (std::size_t k = 0; k < job.request.output_times.size(); k += every) kept.push_back(job.request.output_times[k]);
  job.request.output_times = kept;
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
  const AllocationCount few = allocations_of_a_sample(100, few_times);
  const AllocationCount many = allocations_of_a_sample(1, many_times);
  ASSERT_EQ(few_times, 11u);
  ASSERT_EQ(many_times, 1001u);
  std::printf("[          ] a sample's operator new / malloc calls: %ld / %ld with 11 output times, %ld / %ld with 1001\n",
              few.news, few.mallocs, many.news, many.mallocs);
  EXPECT_GT(few.news, 0) << "the counter counts (a record owns its numbers)";
  EXPECT_EQ(many.news, few.news) << "operator new per sample with 1001 output times against 11";
#if defined(TREEDYN_COUNTS_MALLOC)
  EXPECT_GT(few.mallocs, few.news) << "malloc is counted (SUNDIALS' set-up)";
  EXPECT_EQ(many.mallocs, few.mallocs) << "malloc per sample with 1001 output times against 11";
#endif
}

}  // namespace
}  // namespace treedyn::ensemble
