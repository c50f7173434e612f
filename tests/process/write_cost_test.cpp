// What writing a byte costs (process/write_cost.*): measured with a file
// that has no name, so nothing is left, and refused with the directory and
// the system's words where the file cannot be made or written, or where
// the disk has too little room to measure (root: a small tmpfs).
#include "process/write_cost.hpp"

#include <gtest/gtest.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <string>

#include "process/atomic_file.hpp"
#include "support/command.hpp"

namespace treedyn {
namespace {

namespace fs = std::filesystem;

std::string refusal(const fs::path& dir, std::size_t bytes) {
  try {
    process::measure_write_seconds_per_byte(dir, bytes);
  } catch (const process::FileError& e) {
    return e.what();
  }
  return "(no error)";
}

// A cost per byte between none and a microsecond (1 MB/s in CPU alone,
// slower than any disk): the bound says only that the time is per byte.
TEST(WriteCost, IsMeasuredAndNothingIsLeft) {
  testing::TempDir dir{"write_cost"};
  const double cost = process::measure_write_seconds_per_byte(dir.path(), std::size_t{4} << 20);
  EXPECT_GT(cost, 0.0);
  EXPECT_LT(cost, 1e-6);
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(WriteCost, AMissingDirectoryIsNamed) {
  testing::TempDir dir{"write_cost"};
  const fs::path missing = dir.path() / "missing";
  EXPECT_EQ(refusal(missing, 1024),
            missing.string() + ": cannot measure what writing costs here: cannot create a file (No such file or directory)");
}

// A disk with less than the probe plus kSpareBytesToMeasure free is not
// written at all: a probe must not fill a disk others write to.
TEST(WriteCost, ASmallDiskIsNotFilledToMeasure) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to mount a small tmpfs";
  testing::TempDir dir{"write_cost_small"};
  const fs::path disk = dir.path() / "disk";
  fs::create_directory(disk);
  if (mount("tmpfs", disk.c_str(), "tmpfs", 0, "size=8m") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno) << ")";
  const std::string error = refusal(disk, std::size_t{1} << 20);
  struct statvfs space {};
  statvfs(disk.c_str(), &space);
  umount(disk.c_str());
  EXPECT_EQ(error, disk.string() + ": cannot measure what writing costs here: 8 MiB free, fewer than 70 MiB (not "
                                   "filled to measure)");
  EXPECT_EQ(space.f_bfree, space.f_blocks) << "the probe wrote";
}

// A write that fails (here at the process's file size limit, EFBIG) is
// named, and the file is gone: the directory is as it was.
TEST(WriteCost, AFailedWriteIsNamedAndNothingIsLeft) {
  testing::TempDir dir{"write_cost_limit"};
  rlimit old{};
  getrlimit(RLIMIT_FSIZE, &old);
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);  // the write returns EFBIG instead
  rlimit small = old;
  small.rlim_cur = rlim_t{1} << 20;
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
  const std::string error = refusal(dir.path(), std::size_t{4} << 20);
  setrlimit(RLIMIT_FSIZE, &old);
  std::signal(SIGXFSZ, old_handler);
  EXPECT_EQ(error, dir.path().string() + ": cannot measure what writing costs here: cannot write (File too large)");
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

// Descriptors: none is left open, on success or on failure.
TEST(WriteCost, NoDescriptorIsLeftOpen) {
  testing::TempDir dir{"write_cost_fds"};
  const auto open_descriptors = [] {
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator("/proc/self/fd")) ++n;
    return n;
  };
  const std::size_t before = open_descriptors();
  process::measure_write_seconds_per_byte(dir.path(), std::size_t{1} << 20);
  refusal(dir.path() / "missing", 1024);
  EXPECT_EQ(open_descriptors(), before);
}

}  // namespace
}  // namespace treedyn
