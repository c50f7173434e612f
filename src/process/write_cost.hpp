// What a byte written into a file costs the writing thread's CPU: the
// kernel's copy into its page cache, the start of its writeback, and the
// pages' allocation. Rank 0 pays it for every byte it stores, and it
// differs between machines about tenfold (BENCHMARKS.md, "Rank 0's storing
// is the page cache's"), so --check measures it where the output will go
// instead of assuming the development machine's.
#pragma once

#include <cstddef>
#include <filesystem>

namespace treedyn::process {

// Thread CPU seconds per byte, from `bytes` (> 0) written in pieces of
// `piece` into a file in `dir` without a name (O_TMPFILE, else one
// unlinked as soon as it is made), through a DropBehind as rank 0 writes
// its output: after an untimed lead of kProbeLeadBytes, so that the timed
// bytes reuse pages the probe dropped, as a long run's do where the disk
// keeps up. Not in it: a file system's writeback and a network's transfer
// after the start: a lower bound. Throws
// FileError (the directory and the system's words) when the file cannot be
// created or written (a missing or read-only directory, a full disk), and
// without writing when the file system has less than the lead, `bytes` and
// kSpareBytesToMeasure free: a probe must not fill a disk others write to.
inline constexpr std::size_t kSpareBytesToMeasure = std::size_t{64} << 20;
inline constexpr std::size_t kProbeWindowBytes = std::size_t{1} << 20;  // DropBehind's window and
inline constexpr std::size_t kProbeLeadBytes = std::size_t{5} << 20;    // its lag, 4 MiB, and a window
double measure_write_seconds_per_byte(const std::filesystem::path& dir, std::size_t bytes = std::size_t{16} << 20,
                                      std::size_t piece = std::size_t{256} << 10);

}  // namespace treedyn::process
