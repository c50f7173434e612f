// A sample's heap allocations do not grow with its output times (issue 17:
// recording allocates nothing per output time). The shipped spherical
// pendulum (every quantity recorded, a body point, three perturbations) is
// run over its 10 s with its own 1001 output times and with every 100th of
// them (11), through SampleRunner::run as a rank runs it, after warm-up
// runs that size the recorder's and the trajectory's storage; the
// allocations counted during one more run must be the same number for
// both: operator new (the record, the recorder) and, where malloc is
// counted (not under a sanitizer), every malloc too (the integrator's
// set-up, SUNDIALS' own, per sample). Likewise, a sample's allocations do
// not grow with the number of responses evaluated on it.
#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

#include "ensemble/sample_runner.hpp"
#include "job/job_document.hpp"
#include "job/sample_job.hpp"
#include "support/allocation_counting.inc"

namespace treedyn::ensemble {
namespace {

// Every kind of response, each `copies` times, on the first recorded column.
std::vector<Response> responses_of_every_kind(int copies) {
  std::vector<Response> out;
  for (int copy = 0; copy < copies; ++copy)
    for (const auto& [reduce, name] : kResponseReduceNames) {
      Response r;
      r.name = std::string(name) + std::to_string(copy);
      r.reduce = reduce;
      r.time = 5.0;
      r.threshold = 0.1;
      out.push_back(r);
    }
  return out;
}

// Allocations during sample 3's run, after runs of samples 1 and 2, with
// every `every`-th output time of the job and `responses` evaluated.
AllocationCount allocations_of_a_sample(std::size_t every, std::size_t& times,
                                        const std::vector<Response>& responses = {}) {
  auto [job, spec] = read_ensemble_job(JobDocument::read(TREEDYN_JOBS_DIR "/spherical_pendulum.toml"));
  spec.responses = responses;
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
  EXPECT_EQ(r.responses.size(), responses.size());
  times = runner.times();
  return {after.news - before.news, after.mallocs - before.mallocs};
}

TEST(SampleAllocations, DoNotGrowWithTheOutputTimes) {
  std::size_t few_times = 0, many_times = 0;
  const AllocationCount few = allocations_of_a_sample(100, few_times);
  const AllocationCount many = allocations_of_a_sample(1, many_times);
  ASSERT_EQ(few_times, 11u);
  ASSERT_EQ(many_times, 1001u);
  std::printf(
      "[          ] a sample's operator new / malloc calls: %ld / %ld with 11 output times, %ld / %ld with 1001\n",
      few.news, few.mallocs, many.news, many.mallocs);
  EXPECT_GT(few.news, 0) << "the counter counts (a record owns its numbers)";
  EXPECT_EQ(many.news, few.news) << "operator new per sample with 1001 output times against 11";
#if defined(TREEDYN_COUNTS_MALLOC)
  EXPECT_GT(few.mallocs, few.news) << "malloc is counted (SUNDIALS' set-up)";
  EXPECT_EQ(many.mallocs, few.mallocs) << "malloc per sample with 1001 output times against 11";
#endif
}

TEST(SampleAllocations, DoNotGrowWithTheResponses) {
  std::size_t times = 0;
  const AllocationCount one_each = allocations_of_a_sample(1, times, responses_of_every_kind(1));
  const AllocationCount four_each = allocations_of_a_sample(1, times, responses_of_every_kind(4));
  std::printf("[          ] a sample's operator new / malloc calls: %ld / %ld with 8 responses, %ld / %ld with 32\n",
              one_each.news, one_each.mallocs, four_each.news, four_each.mallocs);
  EXPECT_EQ(four_each.news, one_each.news) << "operator new per sample with 32 responses against 8";
#if defined(TREEDYN_COUNTS_MALLOC)
  EXPECT_EQ(four_each.mallocs, one_each.mallocs) << "malloc per sample with 32 responses against 8";
#endif
}

}  // namespace
}  // namespace treedyn::ensemble
