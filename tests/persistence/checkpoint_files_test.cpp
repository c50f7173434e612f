// The checkpoint files on their own (src/persistence/checkpoint.hpp), without
// MPI: what a rank saves in several frames comes back record for record,
// through a resume's consolidation too, and a damaged frame is refused. The
// frames are built in place (a header filled in at save), so these check
// that header against the reader's own framing.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "ensemble/rank_results.hpp"
#include "persistence/checkpoint.hpp"
#include "process/atomic_file.hpp"

namespace {

namespace fs = std::filesystem;
using namespace treedyn;
using namespace treedyn::ensemble;
using namespace treedyn::persistence;

constexpr std::size_t kTimes = 3, kColumns = 2, kSamples = 7;
constexpr int kBins = 4;

// Sample k: sample 3 failed (a reason, no statistics), the others are ok.
SampleRecord record(std::uint64_t k) {
  SampleRecord r;
  r.index = k;
  r.time_reached = k == 3 ? 0.25 : 1.0;
  r.inputs = {0.5 + static_cast<double>(k), -1.0};
  r.reductions = {1.0 * static_cast<double>(k), 2.0, -3.0, 4.5};
  r.final_state = {1.0, 0.0, 0.0, 0.0, 0.1, 0.2, static_cast<double>(k)};
  if (k == 3) {
    r.status = SampleStatus::integration_failed;
    r.reason = "step size too small";
  }
  return r;
}

std::vector<double> trajectory(std::uint64_t k) {
  std::vector<double> t(kTimes * kColumns);
  for (std::size_t e = 0; e < t.size(); ++e) t[e] = static_cast<double>(e) + 0.125 * static_cast<double>(k);
  return t;
}

class CheckpointFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("treedyn_checkpoint_files_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    const std::vector<double> nominal = trajectory(0), zero(nominal.size(), 0.0), scale(kColumns, 1.0);
    calibration_ = statistics::calibrate(nominal, zero, zero, scale, kColumns, kBins);
    write_checkpoint_common(dir_, id_, nominal, calibration_, tolerance());
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Samples 0..kSamples-1 kept and saved in three frames (after 2, 5 and 7).
  void save_in_three_frames() {
    RankCheckpoint checkpoint(dir_, id_, 0, "rank0");
    statistics::EnsembleStatistics stats(kTimes, kColumns, kBins, calibration_);
    for (std::uint64_t k = 0; k < kSamples; ++k) {
      const SampleRecord r = record(k);
      if (r.status == SampleStatus::ok) stats.add_sample(trajectory(k));
      checkpoint.add(r);
      if (k == 1 || k == 4 || k == kSamples - 1) checkpoint.save(stats);
    }
    EXPECT_EQ(checkpoint.saved_records(), kSamples);
    EXPECT_FALSE(checkpoint.has_unsaved());
  }

  std::optional<RestoredRun> load(std::uint64_t samples = kSamples) {
    RecordShape shape;
    shape.end = samples;
    shape.inputs = 2;
    shape.reductions = 4;
    shape.final_state = 7;
    return load_checkpoint(dir_, id_, {kTimes, kColumns, kBins}, shape);
  }

  // The pilot's tolerance check, as common.state carries it.
  static statistics::ToleranceCheck tolerance() {
    return statistics::check_tolerances(1e-8, 1e-10, 1, {1.0, 2.0, 4.0}, {1.25});
  }

  static void expect_every_record(const RestoredRun& restored) {
    EXPECT_EQ(restored.tolerance.samples, tolerance().samples);
    EXPECT_EQ(restored.tolerance.change, tolerance().change);
    EXPECT_EQ(restored.tolerance.spread, tolerance().spread);
    EXPECT_EQ(restored.tolerance.rtol, 1e-8);
    ASSERT_EQ(restored.records.size(), kSamples);
    for (std::uint64_t k = 0; k < kSamples; ++k) {
      const SampleRecord& got = restored.records[k];
      const SampleRecord want = record(k);
      EXPECT_EQ(got.index, want.index);
      EXPECT_EQ(got.status, want.status);
      EXPECT_EQ(got.reason, want.reason);
      EXPECT_EQ(got.time_reached, want.time_reached);
      EXPECT_EQ(got.inputs, want.inputs);
      EXPECT_EQ(got.reductions, want.reductions);
      EXPECT_EQ(got.final_state, want.final_state);
    }
    ASSERT_TRUE(restored.statistics.has_value());
    EXPECT_EQ(restored.statistics->samples(), kSamples - 1);  // sample 3 failed
  }

  fs::path dir_;
  RunIdentity id_ = run_identity("title = \"checkpoint files\"\n", "test build");
  statistics::Calibration calibration_;
};

TEST_F(CheckpointFiles, RecordsSavedInSeveralFramesComeBackAndSurviveAConsolidation) {
  save_in_three_frames();
  const std::optional<RestoredRun> restored = load();
  ASSERT_TRUE(restored.has_value());
  EXPECT_EQ(restored->generation, 0u);
  expect_every_record(*restored);

  // A resume folds everything into base-1 (one frame of all the records).
  EXPECT_EQ(consolidate_checkpoint(dir_, id_, *restored), 1u);
  EXPECT_FALSE(fs::exists(dir_ / "part-0-rank0.records"));
  const std::optional<RestoredRun> again = load();
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(again->generation, 1u);
  expect_every_record(*again);
}

TEST_F(CheckpointFiles, AFrameWithADamagedByteIsRefused) {
  save_in_three_frames();
  const fs::path records = dir_ / "part-0-rank0.records";
  const auto size = fs::file_size(records);
  ASSERT_GT(size, 64u);
  {
    std::fstream file(records, std::ios::in | std::ios::out | std::ios::binary);
    file.seekg(static_cast<std::streamoff>(size / 2));
    char byte = 0;
    file.read(&byte, 1);
    file.seekp(static_cast<std::streamoff>(size / 2));
    byte = static_cast<char>(byte ^ 0x10);
    file.write(&byte, 1);
  }
  try {
    load();
    FAIL() << "a damaged records file was loaded";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("damaged"), std::string::npos) << e.what();
  }
}

// Records past kSpillBytes go to the records file before any save, so a
// rank's memory stays bounded between saves (300 s apart by default); what
// was spilled counts only once a save's state covers it.
TEST_F(CheckpointFiles, HeldRecordsSpillToTheFileAndCountOnceASaveCoversThem) {
  const std::uint64_t many = 3 * RankCheckpoint::kSpillBytes / 100;  // a record here encodes to > 100 bytes
  RankCheckpoint checkpoint(dir_, id_, 0, "rank0");
  statistics::EnsembleStatistics stats(kTimes, kColumns, kBins, calibration_);
  const auto keep = [&](std::uint64_t k) {
    SampleRecord r = record(k);
    if (k != 3) r.reason.clear(), r.status = SampleStatus::ok, r.time_reached = 1.0;
    if (r.status == SampleStatus::ok) stats.add_sample(trajectory(k));
    checkpoint.add(r);
    EXPECT_LT(checkpoint.held_bytes(), RankCheckpoint::kSpillBytes + 4096) << "sample " << k;
  };
  for (std::uint64_t k = 0; k < many; ++k) keep(k);
  const fs::path records = dir_ / "part-0-rank0.records";
  ASSERT_TRUE(fs::exists(records)) << "nothing spilled after " << many << " records";
  EXPECT_GE(fs::file_size(records), 2 * RankCheckpoint::kSpillBytes);
  EXPECT_TRUE(checkpoint.has_unsaved());
  EXPECT_EQ(load(many)->records.size(), 0u) << "spilled records counted before a save";

  checkpoint.save(stats);
  EXPECT_FALSE(checkpoint.has_unsaved());
  EXPECT_EQ(checkpoint.saved_records(), many);
  std::optional<RestoredRun> restored = load(many);
  ASSERT_TRUE(restored.has_value());
  ASSERT_EQ(restored->records.size(), many);
  for (std::uint64_t k = 0; k < many; k += 997) EXPECT_EQ(restored->records[k].inputs, record(k).inputs) << k;
  EXPECT_EQ(restored->statistics->samples(), many - 1);

  // More spills and no save (a SIGKILL): the file grows, the state does not.
  const auto saved_size = fs::file_size(records);
  for (std::uint64_t k = many; k < 2 * many; ++k) keep(k);
  EXPECT_GT(fs::file_size(records), saved_size);
  restored = load(2 * many);
  ASSERT_TRUE(restored.has_value());
  EXPECT_EQ(restored->records.size(), many);
  EXPECT_EQ(restored->statistics->samples(), many - 1);
}

// A spill that cannot be written (here the records file's name is taken by
// a directory) throws; RankResults then turns this rank's checkpoints off
// with a warning and goes on keeping samples.
TEST_F(CheckpointFiles, ASpillThatFailsTurnsTheRanksCheckpointsOff) {
  fs::create_directories(dir_ / "part-0-rank0.records");
  const std::uint64_t many = 2 * RankCheckpoint::kSpillBytes / 100;
  {
    RankCheckpoint checkpoint(dir_, id_, 0, "rank0");
    bool thrown = false;
    for (std::uint64_t k = 0; k < many && !thrown; ++k) {
      try {
        checkpoint.add(record(k % kSamples));
      } catch (const treedyn::process::FileError& e) {
        thrown = true;
        EXPECT_NE(std::string(e.what()).find("part-0-rank0.records"), std::string::npos) << e.what();
      }
    }
    EXPECT_TRUE(thrown) << "no spill failed";
    // Once an append failed, a save must not write a state after it.
    statistics::EnsembleStatistics stats(kTimes, kColumns, kBins, calibration_);
    EXPECT_THROW(checkpoint.save(stats), treedyn::process::FileError);
    EXPECT_FALSE(fs::exists(dir_ / "part-0-rank0.state"));
  }
  RankResults results;
  results.start_statistics(statistics::EnsembleStatistics(kTimes, kColumns, kBins, calibration_));
  results.use_checkpoint(std::make_unique<RankCheckpoint>(dir_, id_, 0, "rank0"), 300.0);
  ::testing::internal::CaptureStderr();
  for (std::uint64_t k = 0; k < many; ++k) EXPECT_TRUE(results.keep(record(k % kSamples), nullptr)) << k;
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_FALSE(results.checkpointing());
  EXPECT_NE(err.find("checkpoints are off for this rank"), std::string::npos) << err;
  EXPECT_FALSE(results.save());
  EXPECT_FALSE(fs::exists(dir_ / "part-0-rank0.state"));
}

// load_checkpoint reads only the bytes a state names (read_file_prefix):
// at most the file, whatever a damaged state claims (no terabyte buffer),
// and a file it cannot read is an error that names it.
TEST_F(CheckpointFiles, AFilePrefixIsAtMostTheFileAndAnUnreadableFileIsNamed) {
  const fs::path file = dir_ / "ten.bytes";
  std::ofstream(file, std::ios::binary) << "0123456789";
  EXPECT_EQ(treedyn::process::read_file_prefix(file, 4), (std::vector<char>{'0', '1', '2', '3'}));
  EXPECT_EQ(treedyn::process::read_file_prefix(file, 0).size(), 0u);
  EXPECT_EQ(treedyn::process::read_file_prefix(file, std::uint64_t{1} << 40).size(), 10u);
  for (const fs::path& bad : {dir_ / "missing.records", dir_}) {
    try {
      (void)treedyn::process::read_file_prefix(bad, 4);
      ADD_FAILURE() << bad << ": no error";
    } catch (const treedyn::process::FileError& e) {
      EXPECT_NE(std::string(e.what()).find(bad.string()), std::string::npos) << e.what();
    }
  }
}

}  // namespace
