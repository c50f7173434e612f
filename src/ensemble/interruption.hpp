// A graceful stop on SIGTERM or SIGINT (a batch system's time limit, Ctrl-C),
// or SIGUSR1 (which mpirun forwards to every rank without ending the job, so
// that its exit code stays 5; SIGTERM to mpirun itself makes mpirun exit 1):
// the handler only records the signal; the ensemble driver looks at it
// between samples, stops taking work, writes its checkpoint and exits 5.
// A second SIGINT ends the process the default way (the checkpoint on disk is
// always loadable); repeated SIGTERM or SIGUSR1 are ignored.
#pragma once

namespace treedyn {

// Installs the handlers (signals the process ignores stay ignored).
void catch_interruptions();
// The signal received (SIGTERM, SIGINT or SIGUSR1), or 0.
int interruption_signal();
// For tests and for a rank told by another rank: as if a signal came.
void request_interruption(int signal_number);

}  // namespace treedyn
