#include "io/remove_on_signal.hpp"

#include <unistd.h>

#include <csignal>
#include <cstring>
#include <stdexcept>

namespace treedyn::io {
namespace {

// Only async-signal-safe things happen in the handler: unlink, signal, raise.
char guarded_path[4096] = {};
constexpr int kSignals[] = {SIGTERM, SIGINT, SIGHUP};

extern "C" void remove_and_reraise(int signal_number) {
  if (guarded_path[0] != '\0') unlink(guarded_path);
  std::signal(signal_number, SIG_DFL);
  std::raise(signal_number);
}

}  // namespace

RemoveOnSignal::RemoveOnSignal(const std::filesystem::path& path) {
  const std::string text = path.string();
  if (text.size() >= sizeof guarded_path) throw std::length_error("output path too long");
  std::memcpy(guarded_path, text.c_str(), text.size() + 1);
  for (int s : kSignals) std::signal(s, remove_and_reraise);
}

RemoveOnSignal::~RemoveOnSignal() {
  for (int s : kSignals) std::signal(s, SIG_DFL);
  guarded_path[0] = '\0';
}

}  // namespace treedyn::io
