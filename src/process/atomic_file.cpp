#include "process/atomic_file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "process/output_lock.hpp"
#include "process/signals.hpp"

namespace treedyn::process {
namespace fs = std::filesystem;
namespace {

std::string why() { return std::strerror(errno); }

// The directory's own fsync: what makes a rename survive a power cut (the
// new name is an entry in the directory, not in the file). False with
// errno set when the disk failed; true where a directory cannot be opened
// for reading (write and search permission are enough to create files) or
// its file system does not flush directories (EINVAL, as some network and
// FUSE file systems answer): nothing more can be done there.
bool sync_directory(const fs::path& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return errno == EACCES;
  const bool synced = ::fsync(fd) == 0 || errno == EINVAL || errno == EROFS;
  const int error = errno;
  ::close(fd);
  errno = error;
  return synced;
}

}  // namespace

bool write_all(int fd, std::span<const char> bytes) {
  const char* data = bytes.data();
  std::size_t size = bytes.size();
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return false;
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

fs::path directory_of(const fs::path& path) { return path.has_parent_path() ? path.parent_path() : fs::path("."); }

void check_output_path(const fs::path& path) {
  if (path.empty()) throw FileError("output: no output file given");
  const fs::path dir = directory_of(path);
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw FileError("output " + path.string() + ": directory " + dir.string() +
                    " does not exist; create it first or choose another path");
  if (fs::is_directory(path, ec))
    throw FileError("output " + path.string() + ": is a directory; give a file name such as " +
                    (path / "result.h5").string());
  if (::access(dir.c_str(), W_OK) != 0)
    throw FileError("output " + path.string() + ": directory " + dir.string() + " is not writable");
}

AtomicFile::AtomicFile(fs::path path, Create create) : path_(std::move(path)) {
  check_output_path(path_);
  temporary_ = path_;
  temporary_ += ".tmp-" + std::to_string(::getpid());
  registration_ = register_temporary(temporary_.string());
  if (create == Create::by_caller) return;
  fd_ = ::open(temporary_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    const std::string reason = why();
    unregister_temporary(registration_);
    throw FileError(path_.string() + ": cannot create " + temporary_.string() + " (" + reason + ")");
  }
}

AtomicFile::~AtomicFile() {
  if (!committed_) discard();
}

void AtomicFile::discard() noexcept {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  ::unlink(temporary_.c_str());
  unregister_temporary(registration_);
}

void AtomicFile::write(std::span<const char> bytes) {
  if (!write_all(fd_, bytes))
    throw FileError(path_.string() + ": writing " + temporary_.string() + " failed (" + why() + ")");
}

void AtomicFile::commit(Sync sync) {
  // A file the caller created and closed is opened again for its fsync.
  const bool own = fd_ >= 0;
  const int fd = own ? fd_ : ::open(temporary_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw FileError(path_.string() + ": cannot open " + temporary_.string() + " (" + why() + ")");
  const bool synced = sync == Sync::no || ::fsync(fd) == 0;
  const std::string sync_error = synced ? "" : why();
  const bool closed = ::close(fd) == 0;
  fd_ = -1;
  if (!synced || !closed)
    throw FileError(path_.string() + ": writing " + temporary_.string() + " to the disk failed (" +
                    (synced ? why() : sync_error) + "; is the disk full?)");
  if (std::rename(temporary_.c_str(), path_.c_str()) != 0)
    throw FileError(path_.string() + ": cannot rename the finished file into place (" + why() + ")");
  committed_ = true;
  unregister_temporary(registration_);
  if (sync == Sync::yes && !sync_directory(directory_of(path_)))
    throw FileError(path_.string() + ": in place, but its directory " + directory_of(path_).string() +
                    " could not be flushed to the disk (" + why() + "): after a power cut the file may be missing");
}

void write_file_atomically(const fs::path& path, std::span<const char> bytes, AtomicFile::Sync sync) {
  AtomicFile file(path);
  file.write(bytes);
  file.commit(sync);
}

void append_to_file(const fs::path& path, std::span<const char> bytes, AtomicFile::Sync sync) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) throw FileError(path.string() + ": cannot open for appending (" + why() + ")");
  const bool written = write_all(fd, bytes) && (sync == AtomicFile::Sync::no || ::fsync(fd) == 0);
  const std::string reason = written ? "" : why();
  if (::close(fd) != 0 || !written)
    throw FileError(path.string() + ": appending failed (" + (written ? why() : reason) + "; is the disk full?)");
}

void flush_directory(const fs::path& dir) {
  if (!sync_directory(dir))
    throw FileError(dir.string() + ": its entries could not be flushed to the disk (" + why() +
                    "): after a power cut what was made in it may be missing");
}

void flush_file(const fs::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw FileError(path.string() + ": cannot open for flushing (" + why() + ")");
  const bool synced = ::fsync(fd) == 0;
  const std::string reason = synced ? "" : why();
  if (::close(fd) != 0 || !synced)
    throw FileError(path.string() + ": flushing to the disk failed (" + (synced ? why() : reason) + ")");
}

std::vector<char> read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path.string() + ": cannot open for reading (" + why() + ")");
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw FileError(path.string() + ": reading failed");
  return bytes;
}

std::vector<char> read_file_prefix(const fs::path& path, std::uint64_t bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path.string() + ": cannot open for reading (" + why() + ")");
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw FileError(path.string() + ": cannot read its size (" + ec.message() + ")");
  // The file's size bounds the buffer, whatever `bytes` a damaged state claims.
  std::vector<char> out(static_cast<std::size_t>(std::min<std::uintmax_t>(bytes, size)));
  in.read(out.data(), static_cast<std::streamsize>(out.size()));
  if (in.bad() || static_cast<std::size_t>(in.gcount()) != out.size())
    throw FileError(path.string() + ": reading failed");
  return out;
}

std::vector<std::string> remove_stale_temporaries(const fs::path& dir, const std::string& name) {
  std::vector<std::string> removed;
  const std::string marker = name + ".tmp-";
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir.empty() ? fs::path(".") : dir, ec)) {
    const std::string file = entry.path().filename().string();
    const std::size_t at = file.find(".tmp-");
    if (at == std::string::npos || (!name.empty() && file.rfind(marker, 0) != 0)) continue;
    const std::string digits = file.substr(at + 5);
    if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
    const pid_t pid = static_cast<pid_t>(std::stol(digits));
    if (pid == ::getpid() || process_runs(pid)) continue;
    std::error_code remove_error;
    if (fs::remove(entry.path(), remove_error)) removed.push_back(entry.path().string());
  }
  return removed;
}

}  // namespace treedyn::process
