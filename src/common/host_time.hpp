// Where and when a process runs, as its files and locks record it.
#pragma once

#include <string>

namespace treedyn {

// This host's name ("unknown" when it cannot be had).
std::string host_name();
// Now, UTC, ISO 8601 to the second: 2026-12-01T12:00:00Z.
std::string utc_now();

}  // namespace treedyn
