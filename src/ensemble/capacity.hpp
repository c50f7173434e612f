// How many ranks can a job keep busy before rank 0 limits it? Rank 0
// takes in every rank's rows (one writer), so at P ranks it takes in P
// records per sample time; it saturates near P = sample CPU / its CPU per
// record. A record comes either as a record (rank 0 decodes it, lays it
// out as rows and compresses them) or in a unit (hdf5/unit_chunks.hpp: a
// sender did that, rank 0 stores each chunk as it is). Rank 0's CPU per
// record was measured per example on 2 to 64 oversubscribed ranks
// (bench/capacity_benchmark.sh, BENCHMARKS.md "Rank 0's capacity") and is
// modelled here: as records from the encoded size, in units from the
// number of chunks and the unit's rows.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <ostream>
#include <string>

#include "ensemble/sample_rows.hpp"
#include "job/ensemble_spec.hpp"
#include "job/job.hpp"
#include "output/sample_record.hpp"

namespace treedyn::ensemble {

// Rank 0's CPU time per record of `bytes` (encoded, as a sender sends it),
// at 64 ranks (it grows with the ranks: smaller messages), s: a fixed part
// and a part per byte, a least-squares line through the six examples
// (BENCHMARKS.md, "Rank 0's capacity": the fit against each example;
// deflate is most of the per-byte part, and how well a job's rows compress
// moves it).
inline constexpr double kRankZeroFixedSeconds = 7.7e-6;
inline constexpr double kRankZeroSecondsPerByte = 13e-9;
double rank_zero_seconds_per_record(std::size_t bytes);

// A record's encoded size without its stored trajectory: only samples below
// store_trajectories carry one, so rank 0's steady cost is for records
// without (a trajectory can be a hundred times the rest).
std::size_t typical_record_bytes(const SampleRecord& record);

// Rows of a unit (hdf5/unit_chunks.hpp): samples a sending rank runs in a
// row, assembles into one whole chunk of every per-sample dataset and
// compresses itself, so rank 0 stores their rows as they come. The largest
// power of two up to `most` (most_unit_rows) that leaves every rank
// kUnitsPerRank units of the runs (the last units end at different times:
// more units, less idling at the end); 0, every row through rank 0 as a
// record, below kMinUnitRows (at 128 rows a unit of the spherical
// pendulum's 91 chunks costs rank 0 about what its records do:
// BENCHMARKS.md), with one rank, and for subset simulation, whose chains
// are not units.
inline constexpr std::size_t kMinUnitRows = 256, kMaxUnitRows = 4096;
inline constexpr std::uint64_t kUnitsPerRank = 16;
std::size_t unit_rows(const EnsembleSpec& spec, int ranks, std::size_t most = kMaxUnitRows);

// kMaxUnitRows, or the largest power of two below it that keeps every
// chunk within kMaxChunkBytes (a reader's default chunk cache, 1 MiB,
// holds one) and a unit's message within kMaxUnitBytes (the sender holds
// the unit's records, rank 0 receives it whole).
inline constexpr std::size_t kMaxChunkBytes = std::size_t{1} << 20, kMaxUnitBytes = std::size_t{32} << 20;
std::size_t most_unit_rows(const SampleRows& rows);

// Rank 0's CPU time per record that came in a unit of `rows` rows, each
// record `row_bytes` bytes of rows in `datasets` chunks, s: a part per
// record (receiving the unit's message, decoding the stripped record, a
// failed one's reason, the response table), the bytes it stores at
// `write_seconds_per_byte` (the machine's and the file system's:
// process/write_cost.hpp), and a direct chunk write per dataset per unit.
// The bytes stored are the row bytes less what deflate saves:
// kStoredShare of them, the largest share among the examples. The rest is
// fitted to the 64-rank measurements: a median, not a bound, since those
// vary about twofold from run to run (BENCHMARKS.md, "Rank 0's storing is
// the page cache's": the fit, its spread and the shares).
inline constexpr double kUnitRecordSeconds = 1.2e-6;
inline constexpr double kStoredShare = 0.65;
inline constexpr double kChunkWriteSeconds = 5e-6;
double rank_zero_seconds_per_unit_record(std::size_t datasets, std::size_t rows, std::size_t row_bytes,
                                         double write_seconds_per_byte);
// The write cost used where it cannot be measured: the development VM's for
// pages new to it (what a file system that keeps its pages, such as a
// tmpfs, costs there; with rank 0 dropping what is on the disk, a disk's
// costs about a seventh of it): on the safe side (BENCHMARKS.md, as above).
inline constexpr double kDevelopmentWriteSecondsPerByte = 1.9e-9;

struct Capacity {
  std::size_t record_bytes = 0;               // one sample's encoded record
  std::size_t datasets = 0;                   // its per-sample datasets of numbers: a unit's chunks
  std::size_t row_bytes = 0;                  // its rows' bytes in them, before deflate
  std::size_t most_unit_rows = kMaxUnitRows;  // most_unit_rows() of its rows
  double record_seconds = 0.0;                // rank 0's CPU per record sent as a record
  double sample_seconds = 0.0;                // one sample's CPU (at least, when `sample_cut`)
  bool sample_cut = false;                    // the timed sample ran past the budget and was stopped
  // Writing into the output's file system, s per byte: measured in
  // `write_measured_in` (measure_writing), or the development machine's
  // with `write_not_measured` saying why.
  double write_seconds_per_byte = kDevelopmentWriteSecondsPerByte;
  std::string write_measured_in, write_not_measured;
  // Rank 0's CPU per record when units have `unit_rows` rows (0: records).
  double seconds_per_record(std::size_t unit_rows) const;
  // The ranks rank 0 keeps up with when its records come so.
  double ranks(std::size_t unit_rows = 0) const { return sample_seconds / seconds_per_record(unit_rows); }
};

// The most ranks `spec`'s runs keep busy: on P ranks a run has units of
// unit_rows(spec, P) rows (fewer with more ranks, then none), so rank 0's
// cost per record grows with P; the largest P it still keeps up with (at
// most the runs: more ranks would idle), and that run's unit rows.
struct Scale {
  std::uint64_t ranks = 1;
  std::size_t unit_rows = 0;
};
Scale scales_to(const Capacity& c, const EnsembleSpec& spec);

// The datasets, row bytes and most unit rows of a job's per-sample rows.
void count_rows(Capacity& c, const SampleRows& rows);

// The write cost per byte measured in `dir`, with a file without a name
// (process/write_cost.hpp); where that fails, the development machine's
// stays and write_not_measured says why.
void measure_writing(Capacity& c, const std::filesystem::path& dir);

// Times sample 0 on this thread's CPU, up to 3 times within `budget`
// seconds (the nominal run included), the fastest, and models rank 0's
// cost for its record (and counts its datasets); a sample over the budget
// is stopped there.
Capacity measure_capacity(const Job& job, const EnsembleSpec& spec, double budget = 5.0);

// "rank 0 takes in about X records/s of this job's size as records (B
// bytes each), Y/s in units of 1024 rows (D chunks each); at S ms per
// sample (timed now) this job's N runs scale to about Z ranks before rank
// 0 limits them (...)".
void print_capacity(std::ostream& out, const Capacity& c, const EnsembleSpec& spec, const char* timed);

}  // namespace treedyn::ensemble
