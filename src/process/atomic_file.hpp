// The one way treedyn writes a file. The content goes to PATH.tmp-PID in the
// same directory, is flushed to the disk and renamed over PATH, so PATH is
// either absent, the old file, or the complete new one. Until the rename, a
// failure (an exception, a full disk) removes the temporary file, and so
// does a signal that ends the process (process/signals.hpp). Only kill -9
// can leave one behind: remove_stale_temporaries() finds those later.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace treedyn::process {

// A file that could not be written, read or renamed; the message names it
// and says why (the system's own words). Exit code 4 in every command.
class FileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Checks that `path` can become an output file: its directory exists and is
// writable, and it is not itself a directory. Throws FileError saying which.
void check_output_path(const std::filesystem::path& path);

class AtomicFile {
 public:
  // Who creates the temporary file: this class (then write() fills it), or
  // the caller by name (HDF5 creates its own files).
  enum class Create { here, by_caller };
  // Whether commit() forces the content to the disk first (fsync): always,
  // except where a deadline matters more than a power cut (a checkpoint
  // written between a launcher's SIGTERM and its SIGKILL: the page cache
  // outlives the process, not the machine).
  enum class Sync { yes, no };

  // Checks the path (check_output_path) and creates the temporary. Throws FileError.
  explicit AtomicFile(std::filesystem::path path, Create create = Create::here);
  ~AtomicFile();  // removes the temporary unless committed
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  const std::filesystem::path& path() const { return path_; }
  const std::filesystem::path& temporary() const { return temporary_; }
  // Appends (Create::here only). Throws FileError.
  void write(std::span<const char> bytes);
  // Flushes (see Sync) and renames the temporary over the path; with
  // Sync::yes, then flushes the directory, so the new name survives a power
  // cut too (a failure there throws with the file in place). Throws FileError.
  void commit(Sync sync = Sync::yes);

 private:
  void discard() noexcept;

  std::filesystem::path path_, temporary_;
  int fd_ = -1;
  int registration_ = -1;
  bool committed_ = false;
};

void write_file_atomically(const std::filesystem::path& path, std::span<const char> bytes,
                           AtomicFile::Sync sync = AtomicFile::Sync::yes);
inline void write_file_atomically(const std::filesystem::path& path, const std::string& text) {
  write_file_atomically(path, std::span<const char>(text.data(), text.size()));
}

// Appends to a file (created if missing) and, with Sync::yes, flushes it to
// the disk: the append-only half of a checkpoint. Throws FileError.
void append_to_file(const std::filesystem::path& path, std::span<const char> bytes,
                    AtomicFile::Sync sync = AtomicFile::Sync::yes);

// Every byte of `bytes` to the open file `fd`, through short writes and
// interruptions (EINTR). False with errno set.
bool write_all(int fd, std::span<const char> bytes);

// The directory a path's name lives in ("." for a bare name).
std::filesystem::path directory_of(const std::filesystem::path& path);

// A directory's entries (the names made in it) flushed to the disk, where
// its file system does that: what makes a new name survive a power cut.
// Throws FileError.
void flush_directory(const std::filesystem::path& dir);

// The content of a file written earlier without a flush (Sync::no, or
// appended), flushed to the disk now; its name is flush_directory's.
// Throws FileError.
void flush_file(const std::filesystem::path& path);

// The whole file. Throws FileError.
std::vector<char> read_file(const std::filesystem::path& path);
// At most the first `bytes` bytes (fewer when the file is shorter).
std::vector<char> read_file_prefix(const std::filesystem::path& path, std::uint64_t bytes);

// Temporary files `<name>.tmp-PID` in `dir` (any name when `name` is empty)
// whose process no longer runs: removed, and their paths returned. Only
// PIDs of this host can be checked, so a file whose process lives is kept.
std::vector<std::string> remove_stale_temporaries(const std::filesystem::path& dir, const std::string& name);

}  // namespace treedyn::process
