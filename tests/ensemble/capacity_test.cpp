// Rank 0's capacity (ensemble/capacity.*): the record size it models from
// is the codec's own, the timing stops at its budget and says so, and the
// line says what it rests on.
#include "ensemble/capacity.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "ensemble/sample_runner.hpp"
#include "job/sample_job.hpp"
#include "persistence/record_codec.hpp"

namespace {

using namespace treedyn;
using namespace treedyn::ensemble;

EnsembleJob spherical() {
  return read_ensemble_job(JobDocument::read(std::string(TREEDYN_JOBS_DIR) + "/spherical_pendulum.toml"));
}

TEST(Capacity, TheEncodedSizeIsTheCodecsBytes) {
  const auto [job, spec] = spherical();
  SampleRunner runner(job, spec);
  std::vector<double> trajectory;
  SampleRecord record = runner.run(3, false, trajectory);
  record.reason = "a reason of some length";
  std::vector<char> bytes;
  append_record(record, bytes);
  EXPECT_EQ(encoded_size(record), bytes.size());
  record.trajectory.assign(77, 1.0);
  bytes.clear();
  append_record(record, bytes);
  EXPECT_EQ(encoded_size(record), bytes.size());
}

TEST(Capacity, ASampleIsTimedAndItsRecordModelled) {
  const auto [job, spec] = spherical();
  const Capacity c = measure_capacity(job, spec);
  EXPECT_FALSE(c.sample_cut);
  EXPECT_GT(c.sample_seconds, 0.0);
  EXPECT_LT(c.sample_seconds, 5.0);
  SampleRunner runner(job, spec);
  std::vector<double> trajectory;
  EXPECT_EQ(c.record_bytes, encoded_size(runner.run(0, false, trajectory)));
  EXPECT_DOUBLE_EQ(c.record_seconds,
                   kRankZeroFixedSeconds + kRankZeroSecondsPerByte * static_cast<double>(c.record_bytes));
  EXPECT_DOUBLE_EQ(c.ranks(), c.sample_seconds / c.record_seconds);
  std::ostringstream out;
  print_capacity(out, c, "sample 0, timed now");
  EXPECT_NE(out.str().find("rank 0's capacity: it takes in about "), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("(" + std::to_string(c.record_bytes) + " bytes each"), std::string::npos) << out.str();
  EXPECT_EQ(out.str().find("more than"), std::string::npos) << out.str();
}

// Sample 0 stores its trajectory when store_trajectories > 0, but only the
// first few samples do: the record modelled is a typical one, without it
// (the crane's sample 0 is 466 kB with its trajectory, 4.8 kB without).
TEST(Capacity, TheRecordModelledHasNoStoredTrajectory) {
  auto [job, spec] = spherical();
  spec.store_trajectories = 2;
  SampleRunner runner(job, spec);
  std::vector<double> trajectory;
  SampleRecord record = runner.run(0, false, trajectory);
  ASSERT_FALSE(record.trajectory.empty());
  const std::size_t with_trajectory = encoded_size(record);
  const std::size_t typical = typical_record_bytes(record);
  record.trajectory.clear();
  EXPECT_EQ(typical, encoded_size(record));
  const Capacity c = measure_capacity(job, spec);
  EXPECT_EQ(c.record_bytes, typical);
  EXPECT_LT(c.record_bytes * 10, with_trajectory);
}

// A budget of nothing: the sample is stopped at its first output time and
// the line says the sample takes more than that, and the ranks more too.
TEST(Capacity, ASampleOverItsBudgetIsStoppedAndSaidToTakeMore) {
  const auto [job, spec] = spherical();
  const Capacity c = measure_capacity(job, spec, 0.0);
  EXPECT_TRUE(c.sample_cut);
  std::ostringstream out;
  print_capacity(out, c, "sample 0, timed now");
  EXPECT_NE(out.str().find("at more than "), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("scales to more than about "), std::string::npos) << out.str();
}

}  // namespace
