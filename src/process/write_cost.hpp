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

// Thread CPU seconds per byte, from `bytes` (> 0) written in pieces of
// `piece` into a file in `dir` without a name (O_TMPFILE, else one
// unlinked as soon as it is made). Only the page cache's CPU: a file
// system's writeback and a network's transfer are not in it, and on a
// virtual machine that hands freed memory back to its host the pages it
// finds may be cheaper than a long run's (BENCHMARKS.md, as above): a
// lower bound. Throws FileError (the directory and the system's words)
// when the file cannot be created or written (a missing or read-only
// directory, a full disk), and without writing when the file system has
// less than `bytes` + kSpareBytesToMeasure free: a probe must not fill a
// disk others write to.
inline constexpr std::size_t kSpareBytesToMeasure = std::size_t{64} << 20;
double measure_write_seconds_per_byte(const std::filesystem::path& dir, std::size_t bytes = std::size_t{16} << 20,
                                      std::size_t piece = std::size_t{256} << 10);

}  // namespace treedyn::process
