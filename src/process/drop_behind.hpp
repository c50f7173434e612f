// Pages of a file written once, front to back, that its writer does not
// read back (rank 0's output): the kernel would keep every one of them in
// its page cache until memory runs short, so a long run's every byte takes a
// page new to the page cache. Where memory is handed back to a host (a
// virtual machine's free page reporting) a new page costs about nine times
// a reused one (BENCHMARKS.md, "Rank 0 writes through pages it reuses").
// Dropping what is already on the disk lets the next writes reuse those
// pages, and it spares other processes' cache on a shared node.
// The same idea as PostgreSQL's *_flush_after and `dd oflag=nocache`.
#pragma once

#include <cstdint>
#include <string>

namespace treedyn::process {

class DropBehind {
 public:
  // Every `window` bytes the file grows, its newest bytes are sent to the
  // disk (sync_file_range, not waiting) and the pages more than `lag` bytes
  // behind the end, written by then, are dropped (posix_fadvise). A disk
  // slower than the writer makes the writer wait once it is `lag` behind;
  // the output's fsync at the end would wait for the same bytes.
  static constexpr std::uint64_t kWindowBytes = std::uint64_t{4} << 20;
  static constexpr std::uint64_t kLagBytes = std::uint64_t{16} << 20;

  // `fd` stays the caller's; `name` is the file's, for messages.
  DropBehind(int fd, std::string name, std::uint64_t window = kWindowBytes, std::uint64_t lag = kLagBytes);

  // After writes that left the file `end` bytes long. Throws FileError
  // when the disk reports a failed write (EIO, ENOSPC): reported here, it
  // would not be reported again by the file's fsync. File systems without
  // sync_file_range (EINVAL, ESPIPE) are left to the kernel, silently.
  void written_up_to(std::uint64_t end);
  // The same with the file's size now (fstat).
  void after_writes();

  std::uint64_t dropped_below() const { return dropped_; }
  bool active() const { return active_; }

 private:
  bool sync_range(std::uint64_t from, std::uint64_t to, unsigned flags);

  int fd_;
  std::string name_;
  std::uint64_t window_, lag_;
  std::uint64_t sent_ = 0;     // writeback started below this offset
  std::uint64_t dropped_ = 0;  // pages dropped below this offset
  bool active_ = true;
};

}  // namespace treedyn::process
