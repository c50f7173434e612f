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

#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>

namespace treedyn::ensemble {

__extension__ typedef __int128 wide;  // GCC/Clang 128-bit integer

#if defined(__FAST_MATH__)
#error "RoundedSum needs IEEE arithmetic as written: -ffast-math would reassociate (x + 1.5 2^52) - 1.5 2^52 away"
#endif

// The sum of a block's values, each rounded to the nearest integer (ties to
// even, as std::nearbyint in the default rounding mode), exactly, for
// |v| <= 2^100 and at most 2^12 values. Branch-free and in 64-bit integer
// lanes: a value straddling 2^52 or 2^63 at random costs no misprediction,
// and there is no libm nearbyint nor libgcc's soft double -> __int128
// conversion.
//
// v = h 2^50 + r with h = rne(v / 2^50) (|h| <= 2^50) and r = v - h 2^50,
// exact by Sterbenz's lemma (|r| <= 2^49, and r = v when h = 0). h 2^50 is
// an even integer, so rne(v) = h 2^50 + rne(r). Each rne(y), |y| <= 2^51,
// is y + 1.5 2^52, whose ulp is 1: the addition rounds y, and the sum's bit
// pattern minus the constant's is rne(y) as an integer.
struct RoundedSum {
  std::int64_t high = 0;  // sum of h
  std::int64_t low = 0;   // sum of rne(r)

  void add(double v) {
    constexpr double magic = 0x1.8p52;
    const double shifted = v * 0x1p-50 + magic;  // rne(v / 2^50) in its low bits
    const double r = v - (shifted - magic) * 0x1p50;
    high += std::bit_cast<std::int64_t>(shifted) - std::bit_cast<std::int64_t>(magic);
    low += std::bit_cast<std::int64_t>(r + magic) - std::bit_cast<std::int64_t>(magic);
  }
  wide total() const { return wide{high} * (wide{1} << 50) + low; }
};

// A block of pending samples and what they are folded with: sample b's
// value of entry e at rows[b][e], and per entry the calibration (center c,
// scale S, histogram low edge and bin width).
struct FoldBlock {
  const double* const* rows;
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

// RoundedSum's total of `values` (padded with zeros to whole lanes) by the
// fold's own `lanes`-wide sum, for tests: the same as one value at a time.
wide rounded_sum_in_lanes(std::span<const double> values, int lanes);

}  // namespace treedyn::ensemble
