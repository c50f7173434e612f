// Dropping what a writer has put on the disk (process/drop_behind.*): pages
// on the disk more than the lag behind the end leave the page cache
// (mincore), the file reads back as written, a file that cannot be synced is
// left to the kernel, a failed call names the file, and a write the disk
// refuses still reaches the file's fsync (root: a loop device whose backing
// file lies on a small tmpfs, as thin-provisioned storage that runs out).
#include "process/drop_behind.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/magic.h>
#include <sys/mman.h>
#include <sys/vfs.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "process/atomic_file.hpp"
#include "support/command.hpp"
#include "support/loop_disk.hpp"

namespace treedyn {
namespace {

namespace fs = std::filesystem;
constexpr std::uint64_t kMiB = std::uint64_t{1} << 20;

// 256 KiB that differ from piece to piece, so a piece read back from the
// wrong place shows.
std::vector<char> piece_of(std::uint64_t k) {
  std::vector<char> bytes(256 << 10);
  std::mt19937_64 draws(k);
  for (std::size_t i = 0; i < bytes.size(); i += 8) {
    const std::uint64_t v = draws();
    std::memcpy(bytes.data() + i, &v, 8);
  }
  return bytes;
}

// Pages of [from, to) of `fd`'s file in the page cache.
std::size_t resident_pages(int fd, std::uint64_t from, std::uint64_t to) {
  const std::size_t page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  void* map = mmap(nullptr, to - from, PROT_READ, MAP_SHARED, fd, static_cast<off_t>(from));
  if (map == MAP_FAILED) throw std::runtime_error(std::string("mmap: ") + std::strerror(errno));
  std::vector<unsigned char> in((to - from + page - 1) / page);
  const int status = mincore(map, to - from, in.data());
  munmap(map, to - from);
  if (status != 0) throw std::runtime_error(std::string("mincore: ") + std::strerror(errno));
  std::size_t n = 0;
  for (unsigned char c : in) n += c & 1u;
  return n;
}

// The writer here waits for the disk after every window (fdatasync), so
// every page is on the disk when its turn to be dropped comes: all of them
// must go. (Rank 0 does not wait: a page still being written is skipped.)
TEST(DropBehind, PagesOnTheDiskLeaveTheCacheALagBehindAndTheFileIsIntact) {
  testing::TempDir dir{"drop_behind"};
  struct statfs kind {};
  ASSERT_EQ(statfs(dir.path().c_str(), &kind), 0);
  if (kind.f_type == TMPFS_MAGIC) GTEST_SKIP() << "a tmpfs keeps its pages: nothing to drop";
  const fs::path path = dir.path() / "stream";
  const int fd = open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0600);
  ASSERT_GE(fd, 0);
  process::DropBehind drop(fd, path.string(), kMiB, 8 * kMiB);
  const std::uint64_t pieces = 192;  // 48 MiB
  std::uint64_t end = 0;
  for (std::uint64_t k = 0; k < pieces; ++k) {
    const std::vector<char> piece = piece_of(k);
    ASSERT_EQ(pwrite(fd, piece.data(), piece.size(), static_cast<off_t>(end)), static_cast<ssize_t>(piece.size()));
    end += piece.size();
    if (end % kMiB == 0) {
      ASSERT_EQ(fdatasync(fd), 0);
    }
    drop.written_up_to(end);
  }
  ASSERT_TRUE(drop.active());
  // Dropped in whole windows, up to a window and the lag behind the end.
  EXPECT_GE(drop.dropped_below(), end - 9 * kMiB);
  EXPECT_LE(drop.dropped_below(), end - 8 * kMiB);
  const std::size_t page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  const std::size_t behind = drop.dropped_below() / page;
  EXPECT_EQ(resident_pages(fd, 0, drop.dropped_below()), 0u) << "of " << behind;
  // The lag's pages stay: mincore sees pages at all.
  EXPECT_GE(resident_pages(fd, end - 4 * kMiB, end), 4 * kMiB / page * 9 / 10);
  std::vector<char> back(256 << 10);
  for (std::uint64_t k = 0; k < pieces; ++k) {
    ASSERT_EQ(pread(fd, back.data(), back.size(), static_cast<off_t>(k * back.size())),
              static_cast<ssize_t>(back.size()));
    ASSERT_EQ(back, piece_of(k)) << "piece " << k;
  }
  close(fd);
}

// A pipe has no page cache to sync (ESPIPE): nothing is thrown, and the
// rest is left to the kernel.
TEST(DropBehind, AFileThatCannotBeSyncedIsLeftToTheKernel) {
  int ends[2];
  ASSERT_EQ(pipe(ends), 0);
  process::DropBehind drop(ends[1], "a pipe", kMiB, 2 * kMiB);
  EXPECT_NO_THROW(drop.written_up_to(16 * kMiB));
  EXPECT_FALSE(drop.active());
  EXPECT_EQ(drop.dropped_below(), 0u);
  close(ends[0]);
  close(ends[1]);
}

// A call that fails for another reason (here a closed descriptor) names the
// file and says why, and nothing is tried again.
TEST(DropBehind, AFailedCallNamesTheFile) {
  int ends[2];
  ASSERT_EQ(pipe(ends), 0);
  close(ends[0]);
  close(ends[1]);
  process::DropBehind drop(ends[1], "output out.h5", kMiB, 2 * kMiB);
  std::string error = "(no error)";
  try {
    drop.written_up_to(kMiB);
  } catch (const process::FileError& e) {
    error = e.what();
  }
  EXPECT_EQ(error, "output out.h5: writing to the disk failed (Bad file descriptor)");
}

// A loop device over a 32 MiB sparse file on a 4 MiB tmpfs
// (support/loop_disk.hpp): its page cache takes 16 MiB, its disk fails from
// about the fourth MiB. The pages whose writeback failed are dropped like
// the others, but the failure must still reach the file's fsync: had
// dropping consumed it, a truncated output would be renamed into place.
TEST(DropBehind, AWriteTheDiskRefusesStillReachesTheFsync) {
  testing::TempDir dir{"drop_behind_disk"};
  testing::LoopOverSmallTmpfs disk(dir.path(), 32, "4m");
  if (!disk.skipped.empty()) GTEST_SKIP() << disk.skipped;
  const int fd = open(disk.device.c_str(), O_WRONLY | O_CLOEXEC);
  ASSERT_GE(fd, 0);
  process::DropBehind drop(fd, "output " + disk.device, kMiB, 2 * kMiB);
  std::uint64_t end = 0;
  for (std::uint64_t k = 0; k < 64; ++k) {  // 16 MiB
    const std::vector<char> piece = piece_of(k);
    ASSERT_EQ(pwrite(fd, piece.data(), piece.size(), static_cast<off_t>(end)), static_cast<ssize_t>(piece.size()));
    end += piece.size();
    try {
      drop.written_up_to(end);  // may see the failure first: then it says so
    } catch (const process::FileError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("output " + disk.device + ": writing to the disk failed (", 0), 0u)
          << e.what();
      break;
    }
  }
  EXPECT_GT(drop.dropped_below(), 4 * kMiB) << "pages past the failure were dropped";
  const int synced = fsync(fd);
  const int error = errno;
  close(fd);
  EXPECT_EQ(synced, -1);
  EXPECT_TRUE(error == EIO || error == ENOSPC) << std::strerror(error);
}

}  // namespace
}  // namespace treedyn
