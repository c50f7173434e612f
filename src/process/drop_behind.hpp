// Pages of a file written once, front to back, that its writer does not
// read back (rank 0's output): the kernel would keep every one of them in
// its page cache until memory runs short, so a long run's every byte takes a
// page new to the page cache. Where memory is handed back to a host (a
// virtual machine's free page reporting) a new page costs about nine times
// a reused one (BENCHMARKS.md, "Rank 0 writes through pages it reuses").
// Dropping what is already on the disk lets the next writes reuse those
// pages, and it spares other processes' cache on a shared node. The same
// idea as PostgreSQL's *_flush_after and `dd oflag=nocache`.
//
// It never waits for the disk, so that a slow or stalled disk cannot stall
// the writer: a page still being written when its turn comes stays in the
// window that each later call drops again, until a lag's worth of writing
// has passed it; after that it stays cached. A write the disk fails is left
// to the file's fsync, which reports it (neither call here consumes the
// error).
#pragma once

#include <cstdint>
#include <string>

namespace treedyn::process {

class DropBehind {
 public:
  // Every `window` bytes the file grows, its new bytes' writeback is started
  // (sync_file_range, SYNC_FILE_RANGE_WRITE) and the pages between 2 `lag`
  // and `lag` bytes behind the end that are on the disk by then are dropped
  // (posix_fadvise, POSIX_FADV_DONTNEED: it skips dirty pages and pages
  // still being written).
  static constexpr std::uint64_t kWindowBytes = std::uint64_t{4} << 20;
  static constexpr std::uint64_t kLagBytes = std::uint64_t{16} << 20;

  // `fd` stays the caller's; `name` is the file's, for messages.
  DropBehind(int fd, std::string name, std::uint64_t window = kWindowBytes, std::uint64_t lag = kLagBytes);

  // After writes that left the file `end` bytes long. Throws FileError when
  // starting the writeback fails (the file system's words: EIO, ENOSPC);
  // file systems without sync_file_range (EINVAL, ESPIPE) are left to the
  // kernel, silently.
  void written_up_to(std::uint64_t end);
  // The same with the file's size now (fstat).
  void after_writes();

  // Drops have been asked for every page below this offset.
  std::uint64_t dropped_below() const { return dropped_; }
  bool active() const { return active_; }

 private:
  int fd_;
  std::string name_;
  std::uint64_t window_, lag_;
  std::uint64_t sent_ = 0;     // writeback started below this offset
  std::uint64_t dropped_ = 0;  // drops asked below this offset
  bool active_ = true;
};

}  // namespace treedyn::process
