// The envelope of every file a run leaves for a later process (checkpoint
// states, part files): a magic number, the kind of file, the identity of the
// job and build that wrote it, the payload, and the hash of all that before
// it. A file of another job or build is refused with both named; a damaged
// one (truncated, a flipped bit) by its hash.
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/bytes.hpp"
#include "common/hash.hpp"
#include "process/atomic_file.hpp"

namespace treedyn::persistence {

// A checkpoint or part file that cannot be used: another job or build, or
// damaged. Bad input (exit 2): the message says what to do.
class CheckpointError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Who may resume whom: the job text and the build.
struct RunIdentity {
  std::string job_hash;  // hash64 of the job file's bytes, hex
  std::string build;     // treedyn version, git commit, build type, compiler, executable hash
  bool operator==(const RunIdentity&) const = default;
};
RunIdentity run_identity(const std::string& job_text, const std::string& build);

enum class StateKind : std::uint32_t { common = 1, part = 2, part_file = 3 };

// Writes an enveloped file atomically as its payload is produced: `payload`
// is called with a writer and appends to it; the bytes go to the disk every
// few MiB, so a large payload is never held twice. Throws process::FileError.
class StateFileWriter {
 public:
  StateFileWriter(const std::filesystem::path& path, StateKind kind, const RunIdentity& id);
  // Appends payload bytes (the writer flushes them to the file now and then).
  ByteWriter& out() { return out_; }
  void flush_if_large();
  // A length and then `bytes`, written straight to the file (no copy).
  void put_large(std::span<const char> bytes);
  void commit(process::AtomicFile::Sync sync);

 private:
  void flush();
  process::AtomicFile file_;
  std::vector<char> buffer_;
  ByteWriter out_{buffer_};
  StreamingHash hash_;  // of everything written so far
};

// A whole enveloped file read and checked: its hash, its kind, and (when
// `expected` is given) its identity. `found`, if given, receives the
// identity the file names. Returns the payload's reader over `bytes`.
ByteReader open_state_file(const std::vector<char>& bytes, StateKind kind, const std::filesystem::path& path,
                           const RunIdentity* expected, RunIdentity* found = nullptr);

// CheckpointError for a DecodeError: "... is damaged (why)". What to remove
// is said by whoever knows what the file is part of (checkpoint.cpp).
[[noreturn]] void refuse_damaged(const DecodeError& e);

}  // namespace treedyn::persistence
