// A unit: the rows [first, first + rows) of every per-sample dataset of
// numbers (ensemble/sample_rows.hpp), one whole chunk of each, assembled and
// compressed by the rank that ran those samples, and sent to rank 0 with
// the samples' records stripped of those rows (index, status, reason,
// inputs, responses: what rank 0 keeps besides the file, for its progress
// and its answers). Rank 0 stores each chunk as it is (H5Dwrite_chunk), so
// its cost per record falls from compressing the rows to one direct write
// per dataset per unit (BENCHMARKS.md, "Rank 0's capacity").
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "ensemble/sample_rows.hpp"
#include "output/sample_record.hpp"

namespace treedyn::h5 {

struct UnitChunk {
  bool deflated = true;  // else stored raw (deflate skipped in its filter mask)
  std::span<const unsigned char> bytes;
};

struct Unit {
  std::uint64_t first = 0, rows = 0;
  std::vector<UnitChunk> chunks;      // one per SampleRows dataset, in its order
  std::vector<SampleRecord> records;  // stripped: no reductions, final state, trajectory
};

class UnitEncoder {
 public:
  explicit UnitEncoder(const ensemble::SampleRows& rows) : rows_(rows) {}
  // The unit of `run` (consecutive samples, one whole chunk of every
  // dataset) appended to `out`. A chunk is deflated at kRowsDeflateLevel
  // unless that shrinks it by less than RowDataset::kWorthShrinking; then
  // it goes raw (random numbers: inputs, final states, extremes). The
  // records are stripped of what the chunks hold.
  void encode(std::span<SampleRecord> run, std::vector<char>& out);

 private:
  const ensemble::SampleRows& rows_;
  std::vector<unsigned char> raw_, stream_;  // reused: no allocation per unit once grown
};

// A unit's message read back; its chunks point into `message` (valid as
// long as it is). Throws
// DecodeError naming `what` when the message is not a unit of `datasets`
// chunks.
Unit decode_unit(std::span<const char> message, std::size_t datasets, const std::string& what);
// ... into `unit`, reusing its vectors (rank 0 decodes every unit into one).
void decode_unit_into(std::span<const char> message, std::size_t datasets, const std::string& what, Unit& unit);

}  // namespace treedyn::h5
