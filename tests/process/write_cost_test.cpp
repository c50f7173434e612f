// What writing a byte costs (process/write_cost.*): measured with a file
// that is unlinked at once, so nothing is left, and refused with the
// directory and the system's words where the file cannot be made or
// written. The full disk needs root to mount a small tmpfs.
#include "process/write_cost.hpp"

#include <gtest/gtest.h>
#include <sys/mount.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <cerrno>
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

// 1 MiB into a 128 KiB disk: the write fails, the file is gone and the
// disk's space is free again.
TEST(WriteCost, AFullDiskIsNamedAndItsSpaceFreed) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to mount a small tmpfs";
  testing::TempDir dir{"write_cost_full"};
  const fs::path disk = dir.path() / "disk";
  fs::create_directory(disk);
  if (mount("tmpfs", disk.c_str(), "tmpfs", 0, "size=128k") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno) << ")";
  const std::string error = refusal(disk, std::size_t{1} << 20);
  const bool empty = fs::is_empty(disk);
  struct statvfs space {};
  statvfs(disk.c_str(), &space);
  umount(disk.c_str());
  EXPECT_EQ(error, disk.string() + ": cannot measure what writing costs here: cannot write (No space left on device)");
  EXPECT_TRUE(empty);
  EXPECT_EQ(space.f_bfree, space.f_blocks) << "the probe's blocks were not freed";
}

}  // namespace
}  // namespace treedyn
