#include "process/output_lock.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iterator>
#include <sstream>

#include "common/host_time.hpp"
#include "process/atomic_file.hpp"

namespace treedyn::process {
namespace fs = std::filesystem;
namespace {

// The batch system's job id, where there is one.
std::string batch_job() {
  for (const char* variable : {"SLURM_JOB_ID", "PBS_JOBID", "LSB_JOBID"})
    if (const char* v = std::getenv(variable); v && *v) return v;
  return "";
}

std::string holder_text(const std::string& command) {
  return "host=" + host_name() + "\npid=" + std::to_string(::getpid()) + "\njob=" + batch_job() +
         "\nstarted=" + utc_now() + "\ncommand=" + command + "\n";
}

LockHolder read_holder(const fs::path& path) {
  std::ifstream in(path);
  LockHolder h;
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t eq = line.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = line.substr(0, eq), value = line.substr(eq + 1);
    if (key == "host") h.host = value;
    if (key == "pid") h.pid = value;
    if (key == "job") h.job = value;
    if (key == "started") h.started = value;
    if (key == "command") h.command = value;
  }
  return h;
}

std::string who(const LockHolder& h) {
  std::string t = "host " + (h.host.empty() ? std::string("?") : h.host) + ", pid " + (h.pid.empty() ? "?" : h.pid);
  if (!h.job.empty()) t += ", job " + h.job;
  if (!h.started.empty()) t += ", started " + h.started;
  if (!h.command.empty()) t += ": " + h.command;
  return t;
}

std::string output_of(const fs::path& lock) {
  std::string s = lock.string();
  return s.substr(0, s.size() - 5);  // without ".lock"
}

[[noreturn]] void refuse(const fs::path& lock, const LockHolder& h, bool record_lock) {
  std::string what = output_of(lock) + " is another run's output (" + who(h) +
                     "): two runs on one output destroy each other's work. Wait for it to end, or stop it (" +
                     (h.job.empty() ? "" : "scancel " + h.job + ", or ") + "kill " + h.pid + " on " + h.host +
                     "), then run this again with --resume to go on from its checkpoint";
  if (!record_lock)
    what += ". This file system has no locks, so a run killed on another host leaves its lock behind: if " +
            (h.job.empty() ? std::string("no process ") + h.pid + " runs on " + h.host
                           : "squeue -j " + h.job + " shows nothing and no process " + h.pid + " runs on " + h.host) +
            ", the lock is stale and `rm " + lock.string() + "` clears it";
  throw OutputLocked(what, h);
}

void write_all(int fd, const std::string& text, const fs::path& path) {
  if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, text.data(), text.size(), 0) != static_cast<ssize_t>(text.size()))
    throw FileError(path.string() + ": cannot write the lock file (" + std::strerror(errno) + ")");
}

bool no_locks_here(int error) { return error == ENOLCK || error == ENOSYS || error == EOPNOTSUPP || error == EINVAL; }

}  // namespace

bool process_runs(long pid) {
  if (pid <= 0) return false;
  if (::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) return false;
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
  const std::size_t close = text.rfind(')');
  return close == std::string::npos || close + 2 >= text.size() || text[close + 2] != 'Z';
}

OutputLock::OutputLock(const fs::path& output, const std::string& command, Mode mode)
    : path_(output.string() + ".lock"), record_lock_(mode == Mode::automatic) {
  // A run that ended between our open and our lock may have removed the
  // file: the lock must be on the file that is at the path, so try again.
  for (int attempt = 0; attempt < 5 && record_lock_; ++attempt)
    if (take_record_lock(command)) return;
  if (!record_lock_) {
    take_exclusive_file(command);
    return;
  }
  throw FileError(path_.string() + ": the lock file kept being replaced; is another run starting and ending on it?");
}

// True when held; false to try again (the file was replaced), or with
// record_lock_ cleared when this file system has no record locks.
bool OutputLock::take_record_lock(const std::string& command) {
  const int fd = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) throw FileError(path_.string() + ": cannot make the lock file (" + std::strerror(errno) + ")");
  struct flock lock {};
  lock.l_type = F_WRLCK;
  lock.l_whence = SEEK_SET;
  if (::fcntl(fd, F_SETLK, &lock) != 0) {
    const int error = errno;
    ::close(fd);
    if (no_locks_here(error)) return record_lock_ = false;
    if (error == EACCES || error == EAGAIN) refuse(path_, read_holder(path_), true);
    throw FileError(path_.string() + ": cannot lock (" + std::strerror(error) + ")");
  }
  struct stat held {
  }, named{};
  if (::fstat(fd, &held) != 0 || ::stat(path_.c_str(), &named) != 0 || held.st_ino != named.st_ino ||
      held.st_dev != named.st_dev) {
    ::close(fd);
    return false;
  }
  fd_ = fd;
  write_all(fd_, holder_text(command), path_);
  return true;
}

void OutputLock::take_exclusive_file(const std::string& command) {
  for (int attempt = 0; attempt < 2; ++attempt) {
    const int fd = ::open(path_.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd >= 0) {
      fd_ = fd;
      write_all(fd_, holder_text(command), path_);
      return;
    }
    if (errno != EEXIST) throw FileError(path_.string() + ": cannot make the lock file (" + std::strerror(errno) + ")");
    const LockHolder h = read_holder(path_);
    if (attempt > 0 || h.host != host_name() || process_runs(std::atol(h.pid.c_str()))) refuse(path_, h, false);
    // Left by a run of this host that no longer runs (killed): ours now.
    std::error_code ec;
    fs::remove(path_, ec);
  }
  refuse(path_, read_holder(path_), false);
}

OutputLock::~OutputLock() {
  if (fd_ < 0) return;
  // Removed while still held, so no other run can have taken it in between;
  // a run that opened the old file before the removal finds it replaced.
  struct stat held {
  }, named{};
  if (::fstat(fd_, &held) == 0 && ::stat(path_.c_str(), &named) == 0 && held.st_ino == named.st_ino &&
      held.st_dev == named.st_dev)
    ::unlink(path_.c_str());
  ::close(fd_);
}

}  // namespace treedyn::process
