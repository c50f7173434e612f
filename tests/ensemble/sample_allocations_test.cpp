// A sample's heap allocations do not grow with its output times (issue 17:
// recording allocates nothing per output time). The same perturbed rod is
// run with 11 and with 1001 output times, every quantity recorded, through
// SampleRunner::run as a rank runs it, after warm-up runs that size the
// recorder's and the trajectory's storage; the C++ allocations counted
// during one more run must be the same number for both. (The integrator's
// own set-up allocates in C, per sample, and is not counted: it does not
// depend on the output times either.) This binary replaces the global
// operator new to count; nothing else links into it.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <string>
#include <vector>

#include "ensemble/sample_runner.hpp"
#include "job/ensemble_spec.hpp"
#include "job/job.hpp"

// Under the sanitizers their runtime owns operator new (a replacement here
// would mix its allocations with ours): the test is skipped there.
#ifndef TREEDYN_SANITIZED
namespace {
std::atomic<long> g_allocations{0};

void* counted(std::size_t bytes, std::size_t alignment = 0) {
  ++g_allocations;
  void* p = alignment > alignof(std::max_align_t)
                ? std::aligned_alloc(alignment, (bytes + alignment - 1) / alignment * alignment)
                : std::malloc(bytes == 0 ? 1 : bytes);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}

// Out of line, so that GCC does not see free() meet a pointer from operator
// new after inlining (-Wmismatched-new-delete): they are this file's pair.
[[gnu::noinline]] void release(void* p) noexcept { std::free(p); }
}  // namespace

void* operator new(std::size_t n) { return counted(n); }
void* operator new[](std::size_t n) { return counted(n); }
void* operator new(std::size_t n, std::align_val_t a) { return counted(n, static_cast<std::size_t>(a)); }
void* operator new[](std::size_t n, std::align_val_t a) { return counted(n, static_cast<std::size_t>(a)); }
void operator delete(void* p) noexcept { release(p); }
void operator delete[](void* p) noexcept { release(p); }
void operator delete(void* p, std::size_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t) noexcept { release(p); }
void operator delete(void* p, std::align_val_t) noexcept { release(p); }
void operator delete[](void* p, std::align_val_t) noexcept { release(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { release(p); }
#else
namespace {
std::atomic<long> g_allocations{0};
}  // namespace
#endif

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

// C++ allocations during sample 3's run, after two runs of samples 1 and 2.
long allocations_of_a_sample(const std::string& step, std::size_t& times) {
  const Job job = parse_job(job_text(step), "rod.toml");
  const EnsembleSpec spec = read_ensemble(job);
  SampleRunner runner(job, spec);
  std::vector<double> trajectory;
  for (std::uint64_t k : {1, 2}) EXPECT_EQ(runner.run(k, false, trajectory).status, SampleStatus::ok);
  const long before = g_allocations.load();
  const SampleRecord r = runner.run(3, false, trajectory);
  const long during = g_allocations.load() - before;
  EXPECT_EQ(r.status, SampleStatus::ok) << r.reason;
  times = runner.times();
  return during;
}

TEST(SampleAllocations, DoNotGrowWithTheOutputTimes) {
#ifdef TREEDYN_SANITIZED
  GTEST_SKIP() << "the sanitizers' runtime owns operator new";
#endif
  std::size_t few_times = 0, many_times = 0;
  const long few = allocations_of_a_sample("0.1", few_times);
  const long many = allocations_of_a_sample("0.001", many_times);
  ASSERT_EQ(few_times, 11u);
  ASSERT_EQ(many_times, 1001u);
  EXPECT_GT(few, 0) << "the counter counts (a record owns its numbers)";
  EXPECT_EQ(many, few) << "allocations per sample with 1001 output times against 11";
}

}  // namespace
}  // namespace treedyn::ensemble
