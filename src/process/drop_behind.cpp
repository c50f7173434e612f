#include "process/drop_behind.hpp"

#include <fcntl.h>
#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "process/atomic_file.hpp"

namespace treedyn::process {

DropBehind::DropBehind(int fd, std::string name, std::uint64_t window, std::uint64_t lag)
    : fd_(fd), name_(std::move(name)), window_(window), lag_(lag) {
  if (window == 0 || lag < window) throw std::invalid_argument("DropBehind: a window > 0 and a lag of one or more");
}

// false where the file system has no such call (left to the kernel).
bool DropBehind::sync_range(std::uint64_t from, std::uint64_t to, unsigned flags) {
  if (::sync_file_range(fd_, static_cast<off_t>(from), static_cast<off_t>(to - from), flags) == 0) return true;
  if (errno == EINVAL || errno == ESPIPE || errno == ENOSYS || errno == EOPNOTSUPP) return false;
  throw FileError(name_ + ": writing to the disk failed (" + std::strerror(errno) + ")");
}

void DropBehind::written_up_to(std::uint64_t end) {
  if (!active_ || end < sent_ + window_) return;
  active_ = sync_range(sent_, end, SYNC_FILE_RANGE_WRITE);
  sent_ = end;
  if (!active_ || end < dropped_ + lag_ + window_) return;
  // Everything below `end - lag` was sent a lag ago: wait for what is still
  // in flight, then drop it (fadvise drops only clean pages).
  const std::uint64_t below = end - lag_;
  active_ =
      sync_range(dropped_, below, SYNC_FILE_RANGE_WAIT_BEFORE | SYNC_FILE_RANGE_WRITE | SYNC_FILE_RANGE_WAIT_AFTER);
  if (active_)
    ::posix_fadvise(fd_, static_cast<off_t>(dropped_), static_cast<off_t>(below - dropped_), POSIX_FADV_DONTNEED);
  dropped_ = below;
}

void DropBehind::after_writes() {
  struct stat status {};
  if (!active_) return;
  if (::fstat(fd_, &status) != 0) throw FileError(name_ + ": cannot see its size (" + std::strerror(errno) + ")");
  written_up_to(static_cast<std::uint64_t>(status.st_size));
}

}  // namespace treedyn::process
