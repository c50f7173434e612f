// What of a checkpoint reaches the disk, and when (src/persistence/checkpoint.hpp).
// A stop signal's save is not flushed (SIGKILL may follow within seconds);
// the run's end then asks for a flushed save of the same state, which must
// flush what that save wrote: the records, the state and their names. The
// checkpoint directory's own name in its parent is flushed when it is made.
// This test binary's own fsync records which file or directory each flush
// was for, and fails them on demand.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "ensemble/rank_results.hpp"
#include "persistence/checkpoint.hpp"
#include "process/atomic_file.hpp"
#include "support/command.hpp"

namespace {
std::vector<std::string> flushed;  // what each fsync was for, in order
int flush_error = 0;               // errno every fsync fails with; 0: they succeed
int flushes_before_error = 0;      // with flush_error: how many succeed first

std::string path_of(int fd) {
  char target[4096];
  const std::string link = "/proc/self/fd/" + std::to_string(fd);
  const ssize_t n = ::readlink(link.c_str(), target, sizeof target - 1);
  return n > 0 ? std::string(target, static_cast<std::size_t>(n)) : std::string();
}
}  // namespace

// Every fsync of the treedyn code linked into this binary comes here.
extern "C" int fsync(int fd) {
  flushed.push_back(path_of(fd));
  if (flush_error != 0 && flushes_before_error-- <= 0) {
    errno = flush_error;
    return -1;
  }
  return static_cast<int>(::syscall(SYS_fsync, fd));
}

namespace treedyn::persistence {
namespace {

namespace fs = std::filesystem;
using process::AtomicFile;

constexpr std::size_t kTimes = 2, kColumns = 1;
constexpr int kBins = 4;

std::size_t count(const std::vector<std::string>& v, const fs::path& p) {
  return static_cast<std::size_t>(std::count(v.begin(), v.end(), p.string()));
}

class CheckpointFlush : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::canonical(temp_.path()) / "out.h5.checkpoint";
    records_ = dir_ / "part-0-rank0.records";
    state_ = dir_ / "part-0-rank0.state";
    create_checkpoint_directory(dir_);
    const std::vector<double> nominal(kTimes * kColumns, 1.0), zero(nominal.size(), 0.0), scale(kColumns, 1.0);
    calibration_ = statistics::calibrate(nominal, zero, zero, scale, kColumns, kBins);
    write_checkpoint_common(dir_, id_, nominal, calibration_, {});
    flushed.clear();
  }

  SampleRecord record(std::uint64_t k) const {
    SampleRecord r;
    r.index = k;
    r.time_reached = 1.0;
    r.final_state = {static_cast<double>(k)};
    return r;
  }
  // How many records the checkpoint restores (samples 0 .. end-1 allowed).
  std::size_t records_restored(std::uint64_t end) const {
    RecordShape shape;
    shape.end = end;
    shape.final_state = 1;
    const auto restored = load_checkpoint(dir_, id_, {kTimes, kColumns, kBins}, shape);
    EXPECT_TRUE(restored.has_value());
    return restored ? restored->records.size() : 0;
  }
  // A rank's results with this checkpoint (saved only when asked) and statistics.
  void start(ensemble::RankResults& results) const {
    results.use_checkpoint(std::make_unique<RankCheckpoint>(dir_, id_, 0, "rank0"), 1e9);
    results.start_statistics(statistics::EnsembleStatistics(kTimes, kColumns, kBins, calibration_));
  }
  void keep(RankCheckpoint& checkpoint, statistics::EnsembleStatistics& stats, std::uint64_t k) {
    stats.add_sample(std::vector<double>(kTimes * kColumns, 0.5 * static_cast<double>(k)));
    checkpoint.add(record(k));
  }

  testing::TempDir temp_{"checkpoint_flush"};
  fs::path dir_, records_, state_;
  RunIdentity id_ = run_identity("title = \"checkpoint flush\"\n", "test build");
  statistics::Calibration calibration_;
};

TEST_F(CheckpointFlush, AFlushedSaveAfterAStopSignalsSaveFlushesWhatThatSaveWrote) {
  RankCheckpoint checkpoint(dir_, id_, 0, "rank0");
  statistics::EnsembleStatistics stats(kTimes, kColumns, kBins, calibration_);
  keep(checkpoint, stats, 0);
  keep(checkpoint, stats, 1);
  checkpoint.save(stats, AtomicFile::Sync::no);  // the stop signal's
  EXPECT_EQ(flushed, std::vector<std::string>{}) << "Sync::no flushes nothing";
  struct stat before {};
  ASSERT_EQ(::stat(state_.c_str(), &before), 0);

  checkpoint.save(stats, AtomicFile::Sync::yes);  // the run's end: nothing new
  // The records the unflushed save appended, the state it wrote, their names.
  EXPECT_EQ(flushed, (std::vector<std::string>{records_.string(), state_.string(), dir_.string()}));
  struct stat after {};
  ASSERT_EQ(::stat(state_.c_str(), &after), 0);
  EXPECT_EQ(after.st_ino, before.st_ino) << "flushed in place, not written again";

  flushed.clear();
  checkpoint.save(stats, AtomicFile::Sync::yes);
  EXPECT_EQ(flushed, std::vector<std::string>{}) << "flushed already: nothing to do";
}

// Records appended without a flush by an unflushed save, then more records
// and a flushed save: the records file's fsync covers both.
TEST_F(CheckpointFlush, AFlushedSaveWithNewRecordsAfterAnUnflushedOneFlushesTheRecordsFile) {
  RankCheckpoint checkpoint(dir_, id_, 0, "rank0");
  statistics::EnsembleStatistics stats(kTimes, kColumns, kBins, calibration_);
  keep(checkpoint, stats, 0);
  checkpoint.save(stats, AtomicFile::Sync::no);
  keep(checkpoint, stats, 1);
  checkpoint.save(stats, AtomicFile::Sync::yes);
  EXPECT_EQ(count(flushed, records_), 1u);
  EXPECT_EQ(count(flushed, dir_), 1u) << "once, after the state's rename";
  // The state is written afresh through AtomicFile: its temporary is flushed.
  EXPECT_EQ(std::count_if(flushed.begin(), flushed.end(),
                          [&](const std::string& p) { return p.rfind(state_.string() + ".tmp-", 0) == 0; }),
            1);
}

// The flush fails (an I/O error): the caller hears it (RankResults turns
// this rank's checkpoints off with a warning), and the saved state stays.
TEST_F(CheckpointFlush, AFlushThatFailsIsAFileErrorAndTheStateStays) {
  RankCheckpoint checkpoint(dir_, id_, 0, "rank0");
  statistics::EnsembleStatistics stats(kTimes, kColumns, kBins, calibration_);
  keep(checkpoint, stats, 0);
  checkpoint.save(stats, AtomicFile::Sync::no);
  flush_error = EIO;
  try {
    checkpoint.save(stats, AtomicFile::Sync::yes);
    ADD_FAILURE() << "no error";
  } catch (const process::FileError& e) {
    EXPECT_EQ(std::string(e.what()), records_.string() + ": flushing to the disk failed (Input/output error)");
  }
  flush_error = 0;
  EXPECT_TRUE(fs::is_regular_file(state_));
  EXPECT_EQ(records_restored(1), 1u);
}

// The run's last save (RankResults::finish): written at once, flushed and
// renamed on a thread of its own while the statistics go on; once awaited,
// the records, then the state's temporary, then the directory were flushed,
// and the state holds every sample kept.
TEST_F(CheckpointFlush, TheRunsLastSaveIsFlushedOnItsOwnThreadRecordsFirst) {
  ensemble::RankResults results;
  start(results);
  for (std::uint64_t k = 0; k < 3; ++k) {
    std::vector<double> trajectory(kTimes * kColumns, 0.5 * static_cast<double>(k));
    ASSERT_TRUE(results.keep(record(k), &trajectory));
  }
  statistics::EnsembleStatistics stats = results.finish();
  stats.add_sample(std::vector<double>(kTimes * kColumns, 9.0));  // the reduction's work goes on meanwhile
  results.await_final_save();
  ASSERT_EQ(flushed.size(), 3u) << ::testing::PrintToString(flushed);
  EXPECT_EQ(flushed[0], records_.string());
  EXPECT_EQ(flushed[1].rfind(state_.string() + ".tmp-", 0), 0u) << flushed[1];
  EXPECT_EQ(flushed[2], dir_.string());
  EXPECT_EQ(records_restored(3), 3u);
  flushed.clear();
  results.await_final_save();
  EXPECT_EQ(flushed, std::vector<std::string>{}) << "awaited already";
}

// That flush fails (an I/O error), at the records or at the state's
// temporary: a warning naming the file, this rank's checkpoints off, no
// temporary left, and the state saved before it stays, whole. The warning
// comes out of await_final_save(), on the main thread, not out of the
// flush's thread whenever it fails (in the middle of rank 0's summary).
TEST_F(CheckpointFlush, ALastSaveThatCannotBeFlushedLeavesTheStateBeforeIt) {
  for (int failing : {0, 1}) {  // the records file's fsync, or the state's temporary's after it
    SCOPED_TRACE(failing);
    ensemble::RankResults results;
    start(results);
    std::vector<double> trajectory(kTimes * kColumns, 0.5);
    ASSERT_TRUE(results.keep(record(0), &trajectory));
    ASSERT_TRUE(results.save());
    trajectory.assign(kTimes * kColumns, 1.5);
    ASSERT_TRUE(results.keep(record(1), &trajectory));
    flushed.clear();
    flush_error = EIO;
    flushes_before_error = failing;
    ::testing::internal::CaptureStderr();
    results.finish();
    // The failed commit turns checkpoints off (under the lock) before its
    // thread ends: once off, the thread has nothing more to say.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (results.checkpointing() && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "") << "warned from the flush's thread";
    ::testing::internal::CaptureStderr();
    results.await_final_save();
    const std::string err = ::testing::internal::GetCapturedStderr();
    flush_error = 0;
    ASSERT_EQ(flushed.size(), static_cast<std::size_t>(failing + 1)) << ::testing::PrintToString(flushed);
    EXPECT_EQ(flushed[0], records_.string());
    const std::string failed = failing == 0 ? records_.string() : flushed[1];
    EXPECT_EQ(failed.rfind(failing == 0 ? records_.string() : state_.string() + ".tmp-", 0), 0u) << failed;
    EXPECT_EQ(err.rfind("warning: ", 0), 0u) << err;
    EXPECT_NE(err.find(failed), std::string::npos) << err;
    EXPECT_NE(err.find("; checkpoints are off for this rank\n"), std::string::npos) << err;
    EXPECT_FALSE(results.checkpointing());
    for (const auto& e : fs::directory_iterator(dir_))
      EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
    EXPECT_EQ(records_restored(2), 1u) << "the state before the failed save";
    fs::remove_all(dir_);  // afresh for the next case
    create_checkpoint_directory(dir_);
    write_checkpoint_common(dir_, id_, std::vector<double>(kTimes * kColumns, 1.0), calibration_, {});
  }
}

TEST_F(CheckpointFlush, ANewCheckpointDirectoryHasItsNameFlushedInItsParent) {
  const fs::path dir = dir_.parent_path() / "second.checkpoint";
  create_checkpoint_directory(dir);
  EXPECT_TRUE(fs::is_directory(dir));
  EXPECT_EQ(flushed, std::vector<std::string>{dir.parent_path().string()});
}

TEST_F(CheckpointFlush, ACheckpointDirectoryThatCannotBeMadeOrFlushedIsAFileError) {
  try {
    create_checkpoint_directory(dir_);
    ADD_FAILURE() << "no error for a directory that exists";
  } catch (const process::FileError& e) {
    EXPECT_EQ(std::string(e.what()), "cannot create the checkpoint directory " + dir_.string() + ": it exists already");
  }
  try {
    create_checkpoint_directory(dir_.parent_path() / "missing" / "out.h5.checkpoint");
    ADD_FAILURE() << "no error for a missing parent";
  } catch (const process::FileError& e) {
    EXPECT_NE(std::string(e.what()).find(": No such file or directory"), std::string::npos) << e.what();
  }
  const fs::path dir = dir_.parent_path() / "third.checkpoint";
  flush_error = EIO;
  try {
    create_checkpoint_directory(dir);
    ADD_FAILURE() << "no error for a parent that cannot be flushed";
  } catch (const process::FileError& e) {
    EXPECT_EQ(std::string(e.what()), dir.parent_path().string() +
                                         ": its entries could not be flushed to the disk (Input/output error): "
                                         "after a power cut what was made in it may be missing");
  }
  flush_error = 0;
}

}  // namespace
}  // namespace treedyn::persistence
