#include "process/write_cost.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "common/host_time.hpp"
#include "process/atomic_file.hpp"

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

}  // namespace

double measure_write_seconds_per_byte(const std::filesystem::path& dir, std::size_t bytes, std::size_t piece) {
  piece = std::max<std::size_t>(1, std::min(piece, bytes));
  const auto failed = [&](const char* what) {
    return FileError(dir.string() + ": cannot measure what writing costs here: " + what + " (" +
                     std::strerror(errno) + ")");
  };
  std::string name = (dir / ".treedyn-write-probe-XXXXXX").string();
  Descriptor file;
  file.fd = ::mkstemp(name.data());
  if (file.fd < 0) throw failed("cannot create a file");
  ::unlink(name.c_str());  // from here on, nothing to leave behind
  const std::vector<char> data = incompressible(piece);
  const double start = thread_cpu_seconds();
  for (std::size_t written = 0; written < bytes; written += piece)
    if (!write_all(file.fd, std::span(data.data(), std::min(piece, bytes - written)))) throw failed("cannot write");
  return (thread_cpu_seconds() - start) / static_cast<double>(std::max<std::size_t>(bytes, 1));
}

}  // namespace treedyn::process
