#include "statistics/block_fold.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace treedyn::statistics {

static_assert(FoldLimits::kSumBits == 62 && FoldLimits::kSquareBits == 60 &&
                  FoldLimits::kMaxScaledDeviation <= 0x1p20 && FoldLimits::kMaxBlock <= 4096,
              "RoundedLaneSum's range: |v| <= 2^100, at most 2^12 values");

// The widths other than 2 need GCC's target pragma (Clang spells it
// differently): elsewhere only 2 lanes, in the same bits.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define TREEDYN_WIDE_FOLDS 1
#else
#define TREEDYN_WIDE_FOLDS 0
#endif

namespace {
namespace lanes2 {
#define TREEDYN_FOLD_LANES 2
#include "statistics/block_fold_lanes.inc"
#undef TREEDYN_FOLD_LANES
}  // namespace lanes2

#if TREEDYN_WIDE_FOLDS
// "avx512f" makes FMA available to GCC (it defines __FP_FAST_FMA), and GCC
// contracts a * b + c by default: this file is compiled with
// -ffp-contract=off (src/CMakeLists.txt) so that no width rounds otherwise.
// (Every product the fold adds today is exact, a power-of-two scaling, so
// a contraction would not change its bits either: a build without the flag
// gave the same states on 60,000 random blocks. The flag keeps it so for
// whatever is added later.)
#pragma GCC push_options
#pragma GCC target("avx2")
namespace lanes4 {
#define TREEDYN_FOLD_LANES 4
#include "statistics/block_fold_lanes.inc"
#undef TREEDYN_FOLD_LANES
}  // namespace lanes4
#pragma GCC pop_options

#pragma GCC push_options
#pragma GCC target("avx512f,avx512dq,avx512vl")
namespace lanes8 {
#define TREEDYN_FOLD_LANES 8
#include "statistics/block_fold_lanes.inc"
#undef TREEDYN_FOLD_LANES
}  // namespace lanes8
#pragma GCC pop_options
#endif
}  // namespace

bool runs_fold_lanes(int lanes) {
#if TREEDYN_WIDE_FOLDS
  __builtin_cpu_init();  // needed when this runs before the constructors that run it
  if (lanes == 8)
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
           __builtin_cpu_supports("avx512vl");
  if (lanes == 4) return __builtin_cpu_supports("avx2");
#endif
  return lanes == 2;
}

int widest_fold_lanes() {
  for (int lanes : {8, 4})
    if (runs_fold_lanes(lanes)) return lanes;
  return 2;
}

void fold_block(const FoldBlock& block, const FoldTotals& totals, int lanes) {
  if (block.samples > FoldLimits::kMaxBlock) throw std::invalid_argument("a block of more than kMaxBlock samples");
  if (!runs_fold_lanes(lanes)) throw std::invalid_argument("this CPU does not fold that many lanes");
  if (block.samples == 0) return;
#if TREEDYN_WIDE_FOLDS
  if (lanes == 8) return lanes8::fold_entries(block, totals);
  if (lanes == 4) return lanes4::fold_entries(block, totals);
#endif
  lanes2::fold_entries(block, totals);
}

wide rounded_sum_in_lanes(std::span<const double> values, int lanes) {
  if (!runs_fold_lanes(lanes)) throw std::invalid_argument("this CPU does not fold that many lanes");
#if TREEDYN_WIDE_FOLDS
  if (lanes == 8) return lanes8::rounded_sum(values);
  if (lanes == 4) return lanes4::rounded_sum(values);
#endif
  return lanes2::rounded_sum(values);
}

}  // namespace treedyn::statistics
