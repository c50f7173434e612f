// Where and when a process runs, as its files and locks record it.
#pragma once

#include <string>

namespace treedyn {

// This host's name ("unknown" when it cannot be had).
std::string host_name();
// Now, UTC, ISO 8601 to the second: 2026-12-01T12:00:00Z.
std::string utc_now();
// CPU time of the calling thread (CLOCK_THREAD_CPUTIME_ID), s: what rank 0's
// own work costs, which oversubscribed ranks do not distort as they do
// wall time.
double thread_cpu_seconds();

}  // namespace treedyn
