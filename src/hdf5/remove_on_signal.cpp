#include "hdf5/remove_on_signal.hpp"

#include <unistd.h>

#include <csignal>
#include <cstring>
#include <stdexcept>

namespace treedyn::h5 {
namespace {

// Only async-signal-safe things happen in the handler: unlink, sigaction, raise.
char guarded_path[4096] = {};
constexpr int kSignals[] = {SIGTERM, SIGINT, SIGHUP};
struct sigaction previous[3];
bool installed[3] = {false, false, false};

int slot(int signal_number) {
  for (int k = 0; k < 3; ++k)
    if (kSignals[k] == signal_number) return k;
  return 0;
}

extern "C" void remove_and_reraise(int signal_number) {
  if (guarded_path[0] != '\0') unlink(guarded_path);
  sigaction(signal_number, &previous[slot(signal_number)], nullptr);  // what was there before
  raise(signal_number);
}

}  // namespace

RemoveOnSignal::RemoveOnSignal(const std::filesystem::path& path) {
  const std::string text = path.string();
  if (text.size() >= sizeof guarded_path) throw std::length_error("output path too long");
  std::memcpy(guarded_path, text.c_str(), text.size() + 1);
  for (int k = 0; k < 3; ++k) {
    struct sigaction current {};
    sigaction(kSignals[k], nullptr, &current);
    // A signal the process ignores (nohup, a background job) stays ignored.
    if (current.sa_handler == SIG_IGN) continue;
    struct sigaction handler {};
    handler.sa_handler = remove_and_reraise;
    sigemptyset(&handler.sa_mask);
    sigaction(kSignals[k], &handler, &previous[k]);
    installed[k] = true;
  }
}

RemoveOnSignal::~RemoveOnSignal() {
  for (int k = 0; k < 3; ++k)
    if (installed[k]) {
      sigaction(kSignals[k], &previous[k], nullptr);
      installed[k] = false;
    }
  guarded_path[0] = '\0';
}

}  // namespace treedyn::h5
