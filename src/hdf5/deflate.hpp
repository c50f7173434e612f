// Deflate (a zlib stream, RFC 1950: what HDF5's deflate filter stores in a
// chunk) coded by libdeflate, for the chunks treedyn compresses itself
// (row_dataset.hpp): libdeflate is about twice as fast as zlib at level 1
// on the per-sample rows (BENCHMARKS.md, "Rank 0 compresses each chunk
// once, with libdeflate") and writes the same format, so every reader
// decodes the chunks with its own zlib.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace treedyn::h5 {

// `bytes` compressed at `level` (0-9, as H5Pset_deflate) into `stream`
// (resized to the stream's length).
void deflate(std::span<const unsigned char> bytes, unsigned level, std::vector<unsigned char>& stream);

// A stream decoded into exactly `bytes`; throws IoError naming `what` when
// the stream is not zlib's, ends early, or holds another length.
void inflate(std::span<const unsigned char> stream, std::span<unsigned char> bytes, const char* what);

}  // namespace treedyn::h5
