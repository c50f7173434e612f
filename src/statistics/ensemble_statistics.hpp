// Streaming ensemble statistics whose result does not depend on the order in
// which samples arrive, nor on how they are split over ranks:
//
//  * sums of d = x - c (c: the nominal trajectory's value) and of d^2 are kept
//    as exact 128-bit fixed-point integers, scaled per entry by S (from the
//    pilot samples): integer addition is associative, so any order and any
//    MPI reduction tree give the same bits;
//  * minimum and maximum are order-independent;
//  * quantiles and histograms come from integer bin counts over a range fixed
//    by the pilot samples (plus under- and overflow counts).
//
// An entry is one output time and one column of the recorded quantities.
// Memory is fixed by (times x columns x bins), never by the number of samples.
//
// Samples are folded in blocks: add_sample copies the trajectory aside, and
// a full block (or any read) is folded a few entries at a time, each in a
// vector lane (block_fold.hpp), so that an entry's sums, extremes and
// histogram stay in cache for all the block's samples instead of one
// histogram cache line per entry and sample. Every update is an exact
// integer addition, a minimum or a maximum: the bits are those of folding
// each sample at once, at any lane width. Reads fold what is pending (the members it
// touches are mutable): a read is not safe alongside another thread's
// access; the ensemble's RankResults holds a lock around both.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "common/bytes.hpp"
#include "statistics/block_fold.hpp"
#include "statistics/calibration.hpp"
#include "statistics/huge_pages.hpp"

namespace treedyn::statistics {

class EnsembleStatistics {
 public:
  // Fixed-point fraction bits of d / S and of (d / S)^2, and the largest
  // |d| / S accepted (beyond it a value is counted as out of range). At the
  // limit a square is 2^100 units, so 2^26 samples fit in 127 bits.
  static constexpr int kSumBits = FoldLimits::kSumBits;
  static constexpr int kSquareBits = FoldLimits::kSquareBits;
  static constexpr double kMaxScaledDeviation = FoldLimits::kMaxScaledDeviation;  // 2^20
  // So the sums cannot overflow, an ensemble has at most 2^26 samples
  // (read_ensemble refuses more).
  static constexpr std::uint64_t kMaxSamples = std::uint64_t{1} << 26;

  EnsembleStatistics(std::size_t times, std::size_t columns, int bins, Calibration calibration);

  // Bytes an accumulator of `entries` entries and `bins` bins holds (its
  // calibration included).
  static double memory_bytes(double entries, int bins);

  // One successful sample's trajectory: times x columns, row-major.
  void add_sample(std::span<const double> trajectory);
  // The same without a copy: takes the trajectory's storage into the block
  // and gives back storage of the same size (its values unspecified) for
  // the next sample.
  void take_sample(std::vector<double>& trajectory);
  // Samples a block holds: up to kMaxBlock, fewer when a block would exceed
  // 16 MiB.
  static constexpr std::size_t kMaxBlock = FoldLimits::kMaxBlock;
  std::size_t block_samples() const { return block_; }
  // Values folded at once: the widest this CPU runs (block_fold.hpp), or
  // another width it runs (for tests and benchmarks; the same bits).
  int fold_lanes() const { return lanes_; }
  void use_fold_lanes(int lanes);

  // Merges another accumulator (same calibration): exact, order-independent.
  void merge(const EnsembleStatistics& other);

  std::size_t times() const { return times_; }
  std::size_t columns() const { return columns_; }
  std::size_t entries() const { return times_ * columns_; }
  int bins() const { return bins_; }
  std::uint64_t samples() const { return samples_; }
  const Calibration& calibration() const { return calibration_; }

  // Results per entry.
  std::uint64_t count(std::size_t entry) const;  // values in the sums
  std::uint64_t out_of_range(std::size_t entry) const;
  double mean(std::size_t entry) const;
  double std_dev(std::size_t entry) const;  // sample standard deviation (n - 1)
  double min(std::size_t entry) const;
  double max(std::size_t entry) const;
  // Quantile q from the histogram, linear inside a bin; within one bin width
  // of the exact sample quantile when it falls inside the histogram range.
  double quantile(std::size_t entry, double q) const;
  // Bin counts: [underflow, bins..., overflow].
  std::span<const std::uint32_t> histogram(std::size_t entry) const;
  double bin_edge(std::size_t entry, int edge) const;

  // The whole state as bytes, in pieces of at most 4096 entries and about
  // 64 MiB (piece 0: the shape, the calibration's hash and the sample
  // count), so that a file or an MPI transfer never needs a second copy of
  // the whole. Histogram counts are written sparse where that is shorter.
  // Adding a state is exact: the result does not depend on the order.
  std::size_t state_pieces() const;
  void write_state_piece(std::size_t piece, ByteWriter& out) const;
  // Adds piece `piece` of a state written by an accumulator of the same
  // shape and calibration. Throws DecodeError for anything else.
  void add_state_piece(std::size_t piece, ByteReader& in);
  // Every piece, one after the other (for tests and small states).
  std::vector<char> state() const;
  void add_state(std::span<const char> bytes, const std::string& what);

 private:
  // Folds the pending samples into the accumulators (logically const: what
  // a read returns is the same before and after).
  void fold_pending() const;
  // Counters per entry: the bins, an underflow and an overflow bin.
  std::size_t counters_per_entry() const { return static_cast<std::size_t>(bins_ + 2); }

  std::size_t times_, columns_;
  int bins_;
  Calibration calibration_;
  std::uint64_t samples_ = 0;  // pending ones included
  std::size_t block_ = 1;      // samples per block
  int lanes_ = widest_fold_lanes();
  mutable std::vector<wide> sum_, square_sum_;
  mutable std::vector<double> min_, max_;
  // entries x (bins + 2): tens of MB, touched at random by every fold
  mutable std::vector<std::uint32_t, HugePageAllocator<std::uint32_t>> counts_;
  mutable std::vector<std::uint64_t> out_of_range_;  // values left out of the sums
  mutable std::vector<std::vector<double>> rows_;    // block_ rows of entries
  mutable std::size_t pending_samples_ = 0;
};

}  // namespace treedyn::statistics
