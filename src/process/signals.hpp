// The one owner of signal handling in a treedyn process.
//
// start_signal_owner(), first thing in main (before MPI_Init, before any
// other thread), blocks SIGTERM, SIGINT, SIGHUP and SIGUSR1 in the calling
// thread, so in every thread started after it (MPI's own included), and
// starts one thread that waits for them with sigwait. Nothing runs in a
// signal handler, so what a signal does may take locks and write files.
//
// What a signal does depends on who is running:
//  * by default, the process ends: the registered temporary files
//    (process/atomic_file.hpp) are removed, and the signal is raised again
//    with its default action, so the exit status says which signal it was;
//  * while a StopOnSignals is alive (an ensemble run), the first signal is
//    recorded (stop_signal()) and the stop's action runs at once on the
//    signal thread: a rank's checkpoint is on disk before a launcher's
//    SIGKILL, even when the main thread is blocked in MPI waiting for a rank
//    that died. The main thread sees stop_signal() between output times,
//    abandons the sample in flight and stops cleanly. A signal within 2 s of
//    the first changes nothing (launchers and process groups deliver one
//    stop twice, and the stop takes well under a second); a later one ends
//    the process at once, as without a StopOnSignals (the checkpoint saved
//    by the first stays loadable), for a rank stuck waiting for a dead one.
// A signal the process ignored when the owner started (nohup) stays ignored.
// SIGPIPE is ignored: a write to a closed pipe fails instead of ending the
// process (`treedyn report F | head -1` still writes the report).
#pragma once

#include <spawn.h>

#include <functional>
#include <string>

namespace treedyn::process {

void start_signal_owner();

// The first signal received while a StopOnSignals was alive, else 0.
// Cheap: an atomic read.
int stop_signal();
// "SIGTERM", "SIGINT", ...
std::string signal_name(int signal_number);

// While alive, signals stop cooperatively: `action` runs on the signal
// thread for the first one (it must be thread-safe against the main thread:
// take the lock the main thread holds while it changes what the action
// reads; an exception it lets out is reported, not fatal). The destructor
// waits for an action in progress. One at a time per process.
class StopOnSignals {
 public:
  explicit StopOnSignals(std::function<void(int)> action = {});
  ~StopOnSignals();
  StopOnSignals(const StopOnSignals&) = delete;
  StopOnSignals& operator=(const StopOnSignals&) = delete;
};

// A file to remove if a signal ends the process (atomic_file.cpp keeps its
// temporaries here). Returns a key for unregister_temporary.
int register_temporary(const std::string& path);
void unregister_temporary(int key);

// For posix_spawn: the child starts with no signal blocked and every caught
// signal at its default (the owner's mask would otherwise be inherited).
class SpawnAttributes {
 public:
  SpawnAttributes();
  ~SpawnAttributes();
  SpawnAttributes(const SpawnAttributes&) = delete;
  SpawnAttributes& operator=(const SpawnAttributes&) = delete;
  const posix_spawnattr_t* get() const { return &attributes_; }

 private:
  posix_spawnattr_t attributes_;
};

}  // namespace treedyn::process
