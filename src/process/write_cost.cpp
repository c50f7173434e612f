#include "process/write_cost.hpp"

#include <fcntl.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/host_time.hpp"
#include "process/atomic_file.hpp"
#include "process/drop_behind.hpp"

namespace treedyn::process {
namespace {

// Bytes no file system can store as holes or compress away (xorshift64).
std::vector<char> incompressible(std::size_t size) {
  std::vector<char> bytes(size);
  std::uint64_t x = 0x9E3779B97F4A7C15u;
  for (char& b : bytes) {
    x ^= x << 13;
    x ^= x >> 7;
    x ^= x << 17;
    b = static_cast<char>(x >> 56);
  }
  return bytes;
}

// An open descriptor that closes itself.
struct Descriptor {
  int fd = -1;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

FileError failed(const std::filesystem::path& dir, const std::string& what, int error) {
  return FileError(dir.string() + ": cannot measure what writing costs here: " + what + " (" + std::strerror(error) +
                   ")");
}

// A file without a name in `dir` (O_TMPFILE: nothing to leave behind even
// when the process is killed), or, where the file system has no such
// files, a named one unlinked at once.
Descriptor unnamed_file(const std::filesystem::path& dir) {
  Descriptor file;
  file.fd = ::open(dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0600);
  if (file.fd >= 0 || (errno != EOPNOTSUPP && errno != EISDIR && errno != EINVAL)) {
    if (file.fd < 0) throw failed(dir, "cannot create a file", errno);
    return file;
  }
  std::string name = (dir / ".treedyn-write-probe-XXXXXX").string();
  file.fd = ::mkostemp(name.data(), O_CLOEXEC);
  if (file.fd < 0) throw failed(dir, "cannot create a file", errno);
  ::unlink(name.c_str());
  return file;
}

}  // namespace

double measure_write_seconds_per_byte(const std::filesystem::path& dir, std::size_t bytes, std::size_t piece) {
  if (bytes == 0) throw std::invalid_argument("measure_write_seconds_per_byte: no bytes to write");
  const std::size_t total = kProbeLeadBytes + bytes;
  struct statvfs space {};
  if (::statvfs(dir.c_str(), &space) == 0 && space.f_bavail * space.f_frsize < kSpareBytesToMeasure + total)
    throw FileError(dir.string() + ": cannot measure what writing costs here: " +
                    std::to_string(space.f_bavail * space.f_frsize >> 20) + " MiB free, fewer than " +
                    std::to_string((kSpareBytesToMeasure + total) >> 20) + " MiB (not filled to measure)");
  piece = std::max<std::size_t>(1, std::min(piece, bytes));
  const Descriptor file = unnamed_file(dir);
  DropBehind drop(file.fd, dir.string() + ": cannot measure what writing costs here", kProbeWindowBytes,
                  kProbeLeadBytes - kProbeWindowBytes);
  const std::vector<char> data = incompressible(piece);
  std::size_t written = 0;
  const auto write_up_to = [&](std::size_t end) {
    for (; written < end; written += std::min(piece, end - written)) {
      if (!write_all(file.fd, std::span(data.data(), std::min(piece, end - written))))
        throw failed(dir, "cannot write", errno);
      drop.written_up_to(written + std::min(piece, end - written));
    }
  };
  write_up_to(kProbeLeadBytes);
  const double start = thread_cpu_seconds();
  write_up_to(total);
  return (thread_cpu_seconds() - start) / static_cast<double>(bytes);
}

}  // namespace treedyn::process
