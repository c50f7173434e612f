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

void DropBehind::written_up_to(std::uint64_t end) {
  if (!active_ || end < sent_ + window_) return;
  if (::sync_file_range(fd_, static_cast<off_t>(sent_), static_cast<off_t>(end - sent_), SYNC_FILE_RANGE_WRITE) != 0) {
    const int error = errno;
    if (error == EINVAL || error == ESPIPE || error == ENOSYS || error == EOPNOTSUPP) {
      active_ = false;  // no such call here: the kernel's own writeback
      return;
    }
    throw FileError(name_ + ": writing to the disk failed (" + std::strerror(error) + ")");
  }
  sent_ = end;
  if (end < lag_ + window_) return;
  // Pages a lag behind were sent a lag ago; those still being written then
  // get another try on each later window, for a lag's worth of writing.
  const std::uint64_t below = end - lag_, from = below > lag_ ? below - lag_ : 0;
  ::posix_fadvise(fd_, static_cast<off_t>(from), static_cast<off_t>(below - from), POSIX_FADV_DONTNEED);
  dropped_ = below;
}

void DropBehind::after_writes() {
  if (!active_) return;
  struct stat status {};
  if (::fstat(fd_, &status) != 0) {
    const int error = errno;
    throw FileError(name_ + ": cannot see its size (" + std::strerror(error) + ")");
  }
  written_up_to(static_cast<std::uint64_t>(status.st_size));
}

}  // namespace treedyn::process
