#include "process/signals.hpp"

#include <pthread.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <map>
#include <mutex>
#include <thread>

namespace treedyn::process {
namespace {

constexpr int kSignals[] = {SIGTERM, SIGINT, SIGHUP, SIGUSR1};

struct Owner {
  std::once_flag started;
  sigset_t watched{};
  // Held while a stop's action runs, and by ~StopOnSignals: an action never
  // outlives its owner. Taken before `state` where both are needed.
  std::mutex action_lock;
  std::mutex state;  // guards everything below
  int stop_depth = 0;
  std::function<void(int)> action;
  std::map<int, std::string> temporaries;
  int next_key = 0;
  std::atomic<int> stop{0};
  std::chrono::steady_clock::time_point first_stop{};
};

// A later signal this soon after the first is the same stop delivered twice.
constexpr auto kRepeatWindow = std::chrono::seconds(2);

Owner& owner() {
  static Owner* o = new Owner;  // never destroyed: the signal thread may outlive main's statics
  return *o;
}

// Removes the temporaries and ends the process by `signal_number`'s default
// action (the exit status names the signal).
[[noreturn]] void end_by(int signal_number) {
  Owner& o = owner();
  {
    std::lock_guard<std::mutex> lock(o.state);
    for (const auto& [key, path] : o.temporaries) ::unlink(path.c_str());
  }
  std::signal(signal_number, SIG_DFL);
  sigset_t one;
  sigemptyset(&one);
  sigaddset(&one, signal_number);
  pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
  std::raise(signal_number);  // this thread: the default action ends the process
  ::_exit(128 + signal_number);
}

// The first stop: record it and run the action; a repeat within the window
// changes nothing. Returns false when the signal must end the process (no
// StopOnSignals alive, or a later signal: someone insists).
bool stop_with(int signal_number) {
  Owner& o = owner();
  std::lock_guard<std::mutex> acting(o.action_lock);
  std::function<void(int)> action;
  {
    std::lock_guard<std::mutex> lock(o.state);
    if (o.stop_depth == 0) return false;
    int expected = 0;
    if (!o.stop.compare_exchange_strong(expected, signal_number))
      return std::chrono::steady_clock::now() - o.first_stop < kRepeatWindow;
    o.first_stop = std::chrono::steady_clock::now();
    action = o.action;
  }
  try {
    if (action) action(signal_number);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "warning: the stop on %s could not save the checkpoint (%s)\n",
                 signal_name(signal_number).c_str(), e.what());
  } catch (...) {
    std::fprintf(stderr, "warning: the stop on %s could not save the checkpoint\n", signal_name(signal_number).c_str());
  }
  return true;
}

void watch() {
  Owner& o = owner();
  for (;;) {
    int signal_number = 0;
    if (sigwait(&o.watched, &signal_number) != 0) continue;
    if (!stop_with(signal_number)) end_by(signal_number);
  }
}

}  // namespace

void start_signal_owner() {
  Owner& o = owner();
  std::call_once(o.started, [&o] {
    sigemptyset(&o.watched);
    for (int s : kSignals) {
      struct sigaction current {};
      sigaction(s, nullptr, &current);
      if (current.sa_handler != SIG_IGN) sigaddset(&o.watched, s);  // nohup's SIGHUP stays ignored
    }
    pthread_sigmask(SIG_BLOCK, &o.watched, nullptr);
    // A closed stdout (a pipe into `head -1`) makes a write fail instead of
    // ending the process: the files are written all the same.
    std::signal(SIGPIPE, SIG_IGN);
    std::thread(watch).detach();
  });
}

int stop_signal() { return owner().stop.load(); }

std::string signal_name(int signal_number) {
  switch (signal_number) {
    case SIGTERM:
      return "SIGTERM";
    case SIGINT:
      return "SIGINT";
    case SIGHUP:
      return "SIGHUP";
    case SIGUSR1:
      return "SIGUSR1";
    default:
      return "signal " + std::to_string(signal_number);
  }
}

StopOnSignals::StopOnSignals(std::function<void(int)> action) {
  Owner& o = owner();
  std::lock_guard<std::mutex> lock(o.state);
  ++o.stop_depth;
  o.action = std::move(action);
}

StopOnSignals::~StopOnSignals() {
  Owner& o = owner();
  std::lock_guard<std::mutex> acting(o.action_lock);
  std::lock_guard<std::mutex> lock(o.state);
  --o.stop_depth;
  o.action = {};
}

int register_temporary(const std::string& path) {
  Owner& o = owner();
  std::lock_guard<std::mutex> lock(o.state);
  o.temporaries.emplace(o.next_key, path);
  return o.next_key++;
}

void unregister_temporary(int key) {
  Owner& o = owner();
  std::lock_guard<std::mutex> lock(o.state);
  o.temporaries.erase(key);
}

SpawnAttributes::SpawnAttributes() {
  posix_spawnattr_init(&attributes_);
  sigset_t none, defaults;
  sigemptyset(&none);
  sigemptyset(&defaults);
  for (int s : kSignals) {
    struct sigaction current {};
    sigaction(s, nullptr, &current);
    if (current.sa_handler != SIG_IGN) sigaddset(&defaults, s);  // an ignored one stays ignored
  }
  sigaddset(&defaults, SIGPIPE);  // ignored here (start_signal_owner), not in a child
  posix_spawnattr_setsigmask(&attributes_, &none);
  posix_spawnattr_setsigdefault(&attributes_, &defaults);
  posix_spawnattr_setflags(&attributes_, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
}

SpawnAttributes::~SpawnAttributes() { posix_spawnattr_destroy(&attributes_); }

}  // namespace treedyn::process
