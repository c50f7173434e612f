#include "ensemble/interruption.hpp"

#include <csignal>
#include <initializer_list>

namespace treedyn {
namespace {

volatile std::sig_atomic_t received = 0;

extern "C" void record_interruption(int signal_number) {
  // A second Ctrl-C means "now". A repeated SIGTERM or SIGUSR1 does not: a
  // batch system and mpirun may both send one within milliseconds, and the
  // stop must still write its checkpoint (SIGKILL ends it if it takes too long).
  if (received != 0 && signal_number == SIGINT) {
    std::signal(signal_number, SIG_DFL);
    std::raise(signal_number);
    return;
  }
  if (received == 0) received = signal_number;
}

}  // namespace

void catch_interruptions() {
  for (int s : {SIGTERM, SIGINT, SIGUSR1}) {
    struct sigaction current {};
    sigaction(s, nullptr, &current);
    if (current.sa_handler == SIG_IGN) continue;
    struct sigaction handler {};
    handler.sa_handler = record_interruption;
    sigemptyset(&handler.sa_mask);
    handler.sa_flags = SA_RESTART;
    sigaction(s, &handler, nullptr);
  }
}

int interruption_signal() { return received; }

void request_interruption(int signal_number) {
  if (received == 0) received = signal_number;
}

}  // namespace treedyn
