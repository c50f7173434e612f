// Rank 0's capacity (ensemble/capacity.*): the record size it models from
// is the codec's own, the timing stops at its budget and says so, and the
// line says what it rests on.
#include "ensemble/capacity.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "ensemble/sample_rows.hpp"
#include "ensemble/sample_runner.hpp"
#include "job/sample_job.hpp"
#include "persistence/record_codec.hpp"
#include "support/command.hpp"

namespace {

using namespace treedyn;
using namespace treedyn::ensemble;
using namespace treedyn::persistence;
namespace fs = std::filesystem;

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
  print_capacity(out, c, spec, "sample 0, timed now");
  EXPECT_NE(out.str().find("rank 0's capacity: it takes in about "), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("(" + std::to_string(c.record_bytes) + " bytes each"), std::string::npos) << out.str();
  EXPECT_EQ(out.str().find("more than"), std::string::npos) << out.str();
  // The chunks a unit carries: the sample's datasets of numbers.
  EXPECT_EQ(c.datasets, SampleRows(spec, runner.layout(), runner.final_state_size()).datasets().size());
  EXPECT_NE(out.str().find("in units of 4096 rows (" + std::to_string(c.datasets) + " chunks each"), std::string::npos)
      << out.str();
  EXPECT_NE(out.str().find("this job's 64 runs scale to about "), std::string::npos) << out.str();
  EXPECT_LE(scales_to(c, spec).ranks, 64u) << "more ranks than runs";
}

// The rule of ensemble/capacity.hpp, case by case: the largest power of two
// up to 4096 (or `most`) with 16 units per rank, none below 256 rows, on one rank, or
// for subset simulation.
TEST(Capacity, UnitRowsFollowTheRunsAndTheRanks) {
  auto [job, spec] = spherical();
  const auto rows = [&](std::uint64_t runs, int ranks) {
    spec.runs = runs;
    return unit_rows(spec, ranks);
  };
  EXPECT_EQ(rows(16 * 2 * 4096, 2), 4096u);
  EXPECT_EQ(rows(16 * 2 * 4096 - 1, 2), 2048u);
  EXPECT_EQ(rows(std::uint64_t{1} << 40, 2), 4096u);
  EXPECT_EQ(unit_rows(spec, 2, 1024), 1024u);  // at most `most`
  EXPECT_EQ(rows(16 * 64 * 512, 64), 512u);
  EXPECT_EQ(rows(16 * 64 * 256, 64), 256u);
  EXPECT_EQ(rows(16 * 64 * 256 - 1, 64), 0u);
  EXPECT_EQ(rows(std::uint64_t{1} << 40, 1), 0u);
  // A stopping rule's waves of `every` runs: units of a wave.
  spec.stop.emplace();
  spec.stop->every = 16 * 2 * 512;
  EXPECT_EQ(rows(std::uint64_t{1} << 40, 2), 512u);
  spec.stop->every = 1000;
  EXPECT_EQ(rows(std::uint64_t{1} << 40, 2), 0u);
  spec.stop.reset();
  spec.design = sampling::Design::subset_simulation;  // its later levels' records come chain by chain
  spec.subset.emplace();
  EXPECT_EQ(rows(std::uint64_t{1} << 40, 2), 0u);
}

// A unit's chunks stay within 1 MiB each (a reader's default chunk cache):
// 300 responses make a 2400-byte row, of which 1 MiB holds 436 rows, so
// units of 256.
TEST(Capacity, UnitsOfWideRowsAreShorter) {
  auto [job, spec] = spherical();
  SampleRunner runner(job, spec);
  EXPECT_EQ(most_unit_rows(SampleRows(spec, runner.layout(), runner.final_state_size())), 4096u);
  spec.responses.resize(300);
  const std::size_t most = most_unit_rows(SampleRows(spec, runner.layout(), runner.final_state_size()));
  EXPECT_EQ(most, 256u);
  spec.runs = std::uint64_t{1} << 40;
  EXPECT_EQ(unit_rows(spec, 2, most), 256u);
}

// scales_to against a plain count: P keeps up when P <= sample / rank 0's
// cost at the unit rows of P ranks; the answer is the last such P before
// the first that does not, or the runs (more ranks would idle).
TEST(Capacity, ScalesToIsTheLastRankCountRankZeroKeepsUpWith) {
  auto [job, spec] = spherical();
  Capacity c;
  c.record_bytes = 2460;
  c.record_seconds = rank_zero_seconds_per_record(c.record_bytes);
  c.datasets = 91;
  for (const double sample : {1.4e-3, 6e-3, 25e-3})
    for (const std::uint64_t runs : {std::uint64_t{5000}, std::uint64_t{2'000'000}, std::uint64_t{50'000'000}}) {
      c.sample_seconds = sample;
      spec.runs = runs;
      std::uint64_t counted = 1;
      while (counted + 1 <= runs &&
             static_cast<double>(counted + 1) <= c.ranks(unit_rows(spec, static_cast<int>(counted + 1))))
        ++counted;
      const Scale scale = scales_to(c, spec);
      EXPECT_EQ(scale.ranks, counted) << sample << " s, " << runs << " runs";
      EXPECT_EQ(scale.unit_rows, unit_rows(spec, static_cast<int>(counted)));
    }
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

// A unit record's cost has a part per byte stored at the write cost (the
// row bytes less deflate's saving), and the row bytes are those the file's
// rows take before deflate (SampleRows::append of one record, every
// dataset).
TEST(Capacity, AUnitRecordCostsItsRowBytesAtTheWriteCost) {
  const auto [job, spec] = spherical();
  SampleRunner runner(job, spec);
  std::vector<double> trajectory;
  const SampleRecord record = runner.run(0, false, trajectory);
  const SampleRows rows(spec, runner.layout(), runner.final_state_size());
  std::vector<unsigned char> bytes;
  for (std::size_t i = 0; i < rows.datasets().size(); ++i) rows.append(i, std::span(&record, 1), bytes);
  Capacity c;
  count_rows(c, rows);
  EXPECT_EQ(c.row_bytes, bytes.size());
  EXPECT_EQ(c.datasets, rows.datasets().size());
  const double cheap = c.seconds_per_record(4096);
  c.write_seconds_per_byte += 1e-9;
  EXPECT_NEAR(c.seconds_per_record(4096) - cheap, 1e-9 * kStoredShare * static_cast<double>(bytes.size()), 1e-15);
}

// --check and a run measure the write cost where the output goes; where
// they cannot, the development machine's is used and the line says why.
TEST(Capacity, WritingIsMeasuredWhereTheOutputGoesOrSaidNotToBe) {
  const auto [job, spec] = spherical();
  treedyn::testing::TempDir dir{"capacity_writing"};
  Capacity c = measure_capacity(job, spec);
  measure_writing(c, dir.path());
  EXPECT_EQ(c.write_measured_in, dir.path().string());
  EXPECT_GT(c.write_seconds_per_byte, 0.0);
  EXPECT_TRUE(fs::is_empty(dir.path()));
  std::ostringstream out;
  print_capacity(out, c, spec, "sample 0, timed now");
  EXPECT_NE(out.str().find("; " + std::to_string(c.row_bytes) + " row bytes a record, about "), std::string::npos)
      << out.str();
  EXPECT_NE(out.str().find(" ns a byte of page-cache CPU measured now in " + dir.path().string() +
                           " (a lower bound: BENCHMARKS.md, \"Rank 0's storing\"); the rest measured on the "
                           "development machine"),
            std::string::npos)
      << out.str();

  const fs::path missing = dir.path() / "missing";
  Capacity d = measure_capacity(job, spec);
  measure_writing(d, missing);
  EXPECT_EQ(d.write_seconds_per_byte, kDevelopmentWriteSecondsPerByte);
  EXPECT_TRUE(d.write_measured_in.empty());
  out.str("");
  print_capacity(out, d, spec, "sample 0, timed now");
  EXPECT_NE(
      out.str().find(" stored, at the development machine's 1.90 ns a byte, not measured here: " + missing.string() +
                     ": cannot measure what writing costs here: cannot create a file "
                     "(No such file or directory); the rest"),
      std::string::npos)
      << out.str();
}

// A budget of nothing: the sample is stopped at its first output time and
// the line says the sample takes more than that, and the ranks more too.
TEST(Capacity, ASampleOverItsBudgetIsStoppedAndSaidToTakeMore) {
  const auto [job, spec] = spherical();
  const Capacity c = measure_capacity(job, spec, 0.0);
  EXPECT_TRUE(c.sample_cut);
  std::ostringstream out;
  print_capacity(out, c, spec, "sample 0, timed now");
  EXPECT_NE(out.str().find("at more than "), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("runs scale to more than about "), std::string::npos) << out.str();
}

}  // namespace
