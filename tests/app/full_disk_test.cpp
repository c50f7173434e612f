// A full disk: `treedyn run` and `treedyn-ensemble` writing into a 256 KiB
// tmpfs exit 4 with one clear message and leave nothing behind (before, the
// ensemble crashed with SIGSEGV inside HDF5's exit handler, exit 139, because
// H5dont_atexit came after the library had initialised itself). Needs root
// (mount); skipped otherwise, with the reason.
#include <gtest/gtest.h>
#include <sys/mount.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "support/command.hpp"
#include "support/ensemble_run.hpp"
#include "support/loop_disk.hpp"

namespace {

namespace fs = std::filesystem;
using namespace treedyn::testing;

class FullDisk : public ::testing::Test {
 protected:
  void SetUp() override {
    if (geteuid() != 0) GTEST_SKIP() << "needs root to mount a small tmpfs";
    fs::create_directory(disk_);
    if (mount("tmpfs", disk_.c_str(), "tmpfs", 0, ("size=" + size()).c_str()) != 0)
      GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno) << ")";
    mounted_ = true;
  }
  void TearDown() override {
    if (mounted_) umount(disk_.c_str());
  }
  virtual std::string size() const { return "256k"; }
  void expect_clean_failure(const CommandResult& r, const std::string& what) {
    std::printf("[%s] exit %d: %s", what.c_str(), r.exit_code, r.err.c_str());
    EXPECT_EQ(r.exit_code, 4) << r.err;
    EXPECT_NE(r.err.find("error: "), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("Segmentation"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("HDF5-DIAG"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::is_empty(disk_)) << "something was left on the full disk";
  }

  // The Kapitza example over 1 s of motion instead of 5: its output (0.9 MiB)
  // still overfills both disks, at a fifth of the cost.
  fs::path kapitza_job() {
    const fs::path job = dir_.path() / "kapitza.toml";
    write_text(job, edited_job_text("kapitza.toml", {{"end_time = 5.0", "end_time = 1.0"}}));
    return job;
  }

  TempDir dir_{"full_disk"};
  fs::path disk_ = dir_.path() / "disk";
  bool mounted_ = false;
};

TEST_F(FullDisk, ALongTrajectoryExitsFourAndLeavesNothing) {
  const auto r =
      run_command(TREEDYN_BINARY,
                  {"run", (fs::path(TREEDYN_JOBS_DIR) / "chain10.toml").string(), "-o", (disk_ / "chain.h5").string()},
                  dir_.path() / "capture");
  expect_clean_failure(r, "treedyn run");
}

TEST_F(FullDisk, AnEnsembleExitsFourAloneAndUnderMpirunAndLeavesNothing) {
  for (int ranks : {0, 2}) {
    const auto r =
        run_ensemble(ranks, kapitza_job(), disk_ / "kapitza.h5", dir_.path() / "capture", {"--checkpoint-every", "0"});
    expect_clean_failure(r, describe(ranks));
  }
}

// As a user runs it (checkpoints every 300 s, the default) on a 1 MiB disk:
// exit 4, and no checkpoint left that would resume nothing. Here the nominal
// run's common.state (0.47 MiB) and the records (0.15 MiB) fit, the rank's
// state (0.48 MiB) does not, then the output (0.9 MiB) fails: before, the
// run left common.state and records that --resume restored 0 samples from.
class FullDiskOneMiB : public FullDisk {
  std::string size() const override { return "1m"; }
};

TEST_F(FullDiskOneMiB, AnEnsembleWithDefaultCheckpointsLeavesNothing) {
  for (int ranks : {0, 2}) {
    const auto r = run_ensemble(ranks, kapitza_job(), disk_ / "kapitza.h5", dir_.path() / "capture");
    expect_clean_failure(r, describe(ranks) + ", default checkpoints");
  }
}

// The checkpoint directory on a full disk: a warning, the run goes on without
// checkpoints where it can, and the output's own failure is exit 4. What
// stays is a checkpoint --resume can load (common.state), or nothing.
TEST_F(FullDisk, CheckpointsOnAFullDiskWarnAndTheRunStillEndsCleanly) {
  const auto r =
      run_ensemble(2, kapitza_job(), disk_ / "kapitza.h5", dir_.path() / "capture", {"--checkpoint-every", "0.1"});
  std::printf("[checkpoints] exit %d: %s", r.exit_code, r.err.c_str());
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_EQ(r.err.find("Segmentation"), std::string::npos) << r.err;
  for (const auto& e : fs::recursive_directory_iterator(disk_))
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
  const fs::path checkpoint = disk_ / "kapitza.h5.checkpoint";
  EXPECT_TRUE(fs::is_empty(disk_) || fs::exists(checkpoint / "common.state"))
      << "a checkpoint directory that nothing could resume from was left";
}

// A disk with room for the output but not for the write-cost probe (the
// probe plus 64 MiB, process/write_cost.hpp): the run is not hurt; its
// capacity line says why writing was not measured, and the disk holds only
// the output.
class SmallDisk : public FullDisk {
  std::string size() const override { return "16m"; }
};

TEST_F(SmallDisk, ARunWhoseDiskCannotSpareTheProbeSaysSoAndSucceeds) {
  const std::vector<std::string> launch = {
      "timeout", "-k", "10", std::to_string(kTimeoutSeconds), TREEDYN_MPIEXEC, "--oversubscribe", "-np", "2"};
  const auto r = run_command(TREEDYN_ENSEMBLE_BINARY,
                             {(fs::path(TREEDYN_JOBS_DIR) / "spherical_pendulum.toml").string(), "-o",
                              (disk_ / "out.h5").string(), "--checkpoint-every", "0"},
                             dir_.path() / "capture", launch);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("not measured here: " + disk_.string() + ": cannot measure what writing costs here: "),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find(" MiB free, fewer than 85 MiB (not filled to measure)"), std::string::npos) << r.err;
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(disk_)) left.push_back(e.path().filename());
  EXPECT_EQ(left, std::vector<std::string>{"out.h5"});
}

// A disk that takes the output into the page cache and fails to write it
// out (support/loop_disk.hpp: ext4 on a 64 MiB image whose tmpfs holds 2
// MiB), as thin-provisioned storage that runs out: every write of the run
// succeeds, rank 0's drop-behind starts the write-out early, and only the
// output's fsync sees the failure. Exit 4 naming the file, and no output,
// temporary or checkpoint left: a truncated file is never renamed into place.
TEST(FailingDisk, AnOutputWhoseWriteOutFailsExitsFourAndLeavesNothing) {
  TempDir dir{"failing_disk"};
  LoopOverSmallTmpfs disk(dir.path(), 64, "2m");
  const fs::path mounted = dir.path() / "disk";
  if (!disk.skipped.empty() || !disk.mount_ext4(mounted)) GTEST_SKIP() << disk.skipped;
  const fs::path job = dir.path() / "kapitza.toml";  // about 4.5 MiB of output: more than the tmpfs holds
  write_text(job, edited_job_text("kapitza.toml", {}));
  const auto r = run_ensemble(2, job, mounted / "kapitza.h5", dir.path() / "capture", {"--checkpoint-every", "0"});
  std::printf("[failing disk] exit %d: %s", r.exit_code, r.err.c_str());
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_NE(r.err.find("error: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("kapitza.h5"), std::string::npos) << "the message names the output: " << r.err;
  EXPECT_EQ(r.err.find("HDF5-DIAG"), std::string::npos) << r.err;
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(mounted))
    if (e.path().filename() != "lost+found") left.push_back(e.path().filename());
  EXPECT_TRUE(left.empty()) << "left on the failing disk: " << left.front();
}

}  // namespace
