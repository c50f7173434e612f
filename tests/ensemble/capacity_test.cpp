// Rank 0's capacity (ensemble/capacity.*): the record size it models from
// is the codec's own, the timing stops at its budget and says so, and the
// line says what it rests on.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "ensemble/capacity.hpp"
#include "ensemble/sample_runner.hpp"
#include "job/sample_job.hpp"
#include "persistence/record_codec.hpp"

namespace {

using namespace treedyn;
using namespace treedyn::ensemble;

EnsembleJob spherical() { return read_ensemble_job(JobDocument::read(std::string(TREEDYN_JOBS_DIR) + "/spherical_pendulum.toml")); }

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
  EXPECT_DOUBLE_EQ(c.record_seconds, kRankZeroFixedSeconds + kRankZeroSecondsPerByte * static_cast<double>(c.record_bytes));
  EXPECT_DOUBLE_EQ(c.ranks(), c.sample_seconds / c.record_seconds);
  std::ostringstream out;
  print_capacity(out, c, "sample 0, timed now");
  EXPECT_NE(out.str().find("rank 0's capacity: it takes in about "), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("(" + std::to_string(c.record_bytes) + " bytes each"), std::string::npos) << out.str();
  EXPECT_EQ(out.str().find("more than"), std::string::npos) << out.str();
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
