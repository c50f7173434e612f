// One output, one owner. A run (or a merge) that will write OUTPUT holds an
// exclusive lock on OUTPUT.lock, beside it, from before it touches OUTPUT,
// its temporary files or OUTPUT.checkpoint/ to the end: a second run on the
// same output refuses at once, naming the holder.
//
// The lock is the operating system's POSIX record lock (fcntl F_SETLK) on
// that file: the kernel drops it when its process ends however it ends
// (SIGKILL included), so a killed run's lock needs no hand-editing. It is
// the lock NFS carries between hosts (NLM for v3, in the protocol for v4;
// flock() is emulated with it there anyway). Where the file system has no
// locks at all (Lustre mounted without -o flock, some FUSE and SMB mounts:
// ENOLCK, ENOSYS, EOPNOTSUPP), the fallback is the file's exclusive
// creation (O_EXCL): then a lock left by a process that no longer runs on
// this host is taken over with a note, and one from another host is
// refused with how to tell whether it is stale and the command that clears it.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace treedyn::process {

// Who holds an output: what the lock file says.
struct LockHolder {
  std::string host, pid, job, started, command;
};

// The output is another run's: what() says whose and what to do.
class OutputLocked : public std::runtime_error {
 public:
  OutputLocked(const std::string& what, LockHolder holder) : std::runtime_error(what), holder_(std::move(holder)) {}
  const LockHolder& holder() const { return holder_; }

 private:
  LockHolder holder_;
};

class OutputLock {
 public:
  // `exclusive_file`: the fallback even where record locks work (its tests).
  enum class Mode { automatic, exclusive_file };

  // Takes the lock of `output` (on OUTPUT.lock; it writes who holds it
  // there: this host, process, the Slurm job where there is one, the start
  // time and `command`). Throws OutputLocked, or FileError when the lock
  // file cannot be made at all.
  OutputLock(const std::filesystem::path& output, const std::string& command, Mode mode = Mode::automatic);
  ~OutputLock();  // removes OUTPUT.lock (still ours) and releases the lock
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

  const std::filesystem::path& path() const { return path_; }
  // How it is held: "fcntl" (the record lock) or "exclusive file" (the fallback).
  const char* kind() const { return record_lock_ ? "fcntl" : "exclusive file"; }

 private:
  bool take_record_lock(const std::string& command);
  void take_exclusive_file(const std::string& command);

  std::filesystem::path path_;
  int fd_ = -1;
  bool record_lock_ = true;
};

// Whether process `pid` runs on this host (not a zombie; one we may not
// signal counts as running).
bool process_runs(long pid);

}  // namespace treedyn::process
