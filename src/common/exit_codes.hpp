// Exit codes of the treedyn commands (documented in docs/commands.md).
#pragma once

namespace treedyn {

enum ExitCode : int {
  kExitOk = 0,
  kExitInternal = 1,     // a bug: please report it
  kExitBadInput = 2,     // job file or command line refused
  kExitIntegration = 3,  // the integrator failed (the message gives the time reached)
  kExitIo = 4,           // an output file could not be written
  kExitInterrupted = 5,  // SIGTERM or SIGINT: stopped cleanly; resumable with --resume
  kExitMemory = 6,       // not enough memory for what the job asks
};

}  // namespace treedyn
