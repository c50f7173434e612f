// What a byte written into a file costs the writing thread's CPU: the
// kernel's copy into its page cache and, where those pages are new to the
// machine, their allocation. Rank 0 pays it for every byte it stores, and
// it differs between machines about tenfold (BENCHMARKS.md, "Rank 0's
// storing is the page cache's"), so --check measures it where the output
// will go instead of assuming the development machine's.
#pragma once

#include <cstddef>
#include <filesystem>

namespace treedyn::process {

// Thread CPU seconds per byte, from `bytes` written in pieces of `piece`
// into a new file in `dir` that is unlinked as soon as it is created:
// nothing is left behind, even when the process is killed. Throws
// FileError (the directory and the system's words) when the file cannot
// be created or written (a missing or read-only directory, a full disk).
double measure_write_seconds_per_byte(const std::filesystem::path& dir, std::size_t bytes = std::size_t{16} << 20,
                                      std::size_t piece = std::size_t{256} << 10);

}  // namespace treedyn::process
