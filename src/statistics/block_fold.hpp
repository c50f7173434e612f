// The fold of a block of samples into the statistics' exact accumulators,
// entry by entry, W values at a time: the block's divisions, the exact
// fixed-point sums, the extremes and the histogram bins in vector lanes
// (GCC's and Clang's vector extension), then one scalar increment per bin.
//
// Every update is an exact integer addition, a minimum or a maximum, so the
// bits do not depend on the lane width: 2 lanes (SSE2, every x86-64), 4
// (AVX2) or 8 (AVX-512F, DQ and VL), chosen once from what the CPU has. The
// wider versions are compiled from the same source (block_fold_lanes.inc)
// under a target pragma, with no contraction into FMA (-ffp-contract=off),
// so that one binary runs everywhere with the same bits.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace treedyn::statistics {

__extension__ typedef __int128 wide;  // GCC/Clang 128-bit integer

// clang-format off
#if defined(__FAST_MATH__)
#error "the fold's rounded sums need IEEE arithmetic as written: -ffast-math would reassociate (x + 1.5 2^52) - 1.5 2^52 away"
#endif
// clang-format on

// A block of pending samples and what they are folded with: sample b's
// value of entry e at rows[b][e], and per entry the calibration (center c,
// scale S, histogram low edge and bin width).
struct FoldBlock {
  const std::vector<double>* rows;
  std::size_t entries, samples;
  const double *center, *scale, *low, *width;
  int bins;
};

// The accumulators a fold updates, per entry: the fixed-point sums of d / S
// and (d / S)^2, the extremes, bins + 2 counters and the out-of-range count.
struct FoldTotals {
  wide *sum, *square_sum;
  double *min, *max;
  std::uint32_t* counts;
  std::uint64_t* out_of_range;
};

// Fixed-point units and limits of the sums (EnsembleStatistics' kSumBits,
// kSquareBits, kMaxScaledDeviation) and the largest block.
struct FoldLimits {
  static constexpr int kSumBits = 62;
  static constexpr int kSquareBits = 60;
  static constexpr double kMaxScaledDeviation = 1048576.0;  // 2^20
  // A fold reads and writes every entry's accumulators (about 0.6 KB with
  // 128 bins) once per block: more samples per block, less of that traffic
  // per sample (the block's own copy is capped by EnsembleStatistics).
  static constexpr std::size_t kMaxBlock = 64;
};

// The widest lane count this CPU runs (8, 4 or 2), and whether it runs
// `lanes` (2 everywhere).
int widest_fold_lanes();
bool runs_fold_lanes(int lanes);

// Folds every entry of `block` into `totals`, `lanes` values at a time
// (the caller checked runs_fold_lanes). At most kMaxBlock samples.
void fold_block(const FoldBlock& block, const FoldTotals& totals, int lanes);

// The sum of `values`, each rounded to the nearest integer (ties to even),
// by the fold's own `lanes`-wide sum (padded with zeros to whole lanes):
// for tests, against std::nearbyint. |v| <= 2^100, at most 2^12 values.
wide rounded_sum_in_lanes(std::span<const double> values, int lanes);

}  // namespace treedyn::statistics
