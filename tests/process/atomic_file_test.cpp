// AtomicFile's commit: the content, then the name. With Sync::yes both
// reach the disk: the file's fsync, the rename, then the directory's fsync
// (the name lives in the directory). This test binary's own fsync counts
// the directories' and fails them on demand.
#include "process/atomic_file.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <string>

#include "support/command.hpp"

namespace {
int directory_syncs = 0;
int directory_sync_error = 0;  // errno a directory's fsync fails with; 0: it succeeds
}  // namespace

// Every fsync of the treedyn code linked into this binary comes here.
extern "C" int fsync(int fd) {
  struct stat st {};
  if (::fstat(fd, &st) == 0 && S_ISDIR(st.st_mode)) {
    ++directory_syncs;
    if (directory_sync_error != 0) {
      errno = directory_sync_error;
      return -1;
    }
  }
  return static_cast<int>(::syscall(SYS_fsync, fd));
}

namespace treedyn {
namespace {

namespace fs = std::filesystem;
using process::AtomicFile;

void write(const fs::path& path, const std::string& text, AtomicFile::Sync sync) {
  process::write_file_atomically(path, std::span<const char>(text.data(), text.size()), sync);
}

TEST(AtomicFile, ASyncedCommitFlushesTheDirectoryAfterTheRename) {
  testing::TempDir dir("atomic");
  const fs::path path = dir.path() / "result.txt";
  directory_syncs = 0;
  write(path, "synced\n", AtomicFile::Sync::yes);
  EXPECT_EQ(directory_syncs, 1);
  EXPECT_EQ(testing::read_text(path), "synced\n");
  write(path, "unsynced\n", AtomicFile::Sync::no);
  EXPECT_EQ(directory_syncs, 1) << "Sync::no flushes nothing";
  EXPECT_EQ(testing::read_text(path), "unsynced\n");
}

// The directory cannot be flushed (an I/O error): the caller hears it, and
// the file is in place, whole, with no temporary left beside it.
TEST(AtomicFile, ADirectoryThatCannotBeFlushedIsAnErrorWithTheFileInPlace) {
  testing::TempDir dir("atomic");
  const fs::path path = dir.path() / "result.txt";
  directory_sync_error = EIO;
  try {
    write(path, "content\n", AtomicFile::Sync::yes);
    ADD_FAILURE() << "no error";
  } catch (const process::FileError& e) {
    EXPECT_EQ(std::string(e.what()), path.string() + ": in place, but its directory " + dir.path().string() +
                                         " could not be flushed to the disk (Input/output error): after a power "
                                         "cut the file may be missing");
  }
  directory_sync_error = 0;
  EXPECT_EQ(testing::read_text(path), "content\n");
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path())) ++entries;
  EXPECT_EQ(entries, 1u);
}

// A file system that does not flush directories (EINVAL) is no error: the
// file is in place and nothing more can be done there.
TEST(AtomicFile, AFileSystemThatDoesNotFlushDirectoriesIsNoError) {
  testing::TempDir dir("atomic");
  const fs::path path = dir.path() / "result.txt";
  directory_sync_error = EINVAL;
  directory_syncs = 0;
  EXPECT_NO_THROW(write(path, "content\n", AtomicFile::Sync::yes));
  directory_sync_error = 0;
  EXPECT_EQ(directory_syncs, 1);
  EXPECT_EQ(testing::read_text(path), "content\n");
}

}  // namespace
}  // namespace treedyn
