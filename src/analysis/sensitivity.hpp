// Sensitivity of a response to the sampled inputs, from per-sample values
// alone (no model): the rank measures every design has (a design's own
// measures are in its folder: designs/saltelli/sobol_indices.hpp,
// designs/morris/morris_effects.hpp). Pure functions of their arguments,
// so the same records give the same bits on any number of ranks.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "analysis/ranking.hpp"

namespace treedyn::analysis {

// Ranks 1..n of `values`; ties share the mean of their ranks. +-inf rank as
// the extremes; NaN is not allowed (callers drop those rows).
std::vector<double> average_ranks(std::span<const double> values);

struct RankSensitivity {
  std::vector<double> spearman;  // per input: Spearman's rank correlation with the response
  std::vector<double> srrc;      // per input: standardised rank regression coefficient
  double r_squared = 0.0;        // of the rank regression: SRRC explain this share of the
                                 // rank variance (trust them when it is near 1); NaN with the SRRC
  std::size_t samples = 0;       // rows used
  // The inputs ranked by |SRRC| where every SRRC is defined, else by
  // |Spearman| (`ranked_by_srrc` says which), with the bootstrap over rows.
  Ranking ranking;
  bool ranked_by_srrc = false;
  std::vector<double> measure_ci;  // per input: 95 % bootstrap interval of |SRRC| or |Spearman| (low, high)
};

// Bootstrap work above which rank_sensitivity draws fewer resamples than
// asked: about n (D + 1)^2 / 2 multiply-adds per resample (a covariance
// matrix of the ranks); this many keeps the bootstrap to seconds on one core.
inline constexpr double kRankBootstrapBudget = 2e10;
inline constexpr int kRankBootstrapMinimum = 50;  // fewer than this: no intervals at all

// `inputs`: n rows x `dimensions` columns, row-major; `response`: n values.
// A constant input or response gives NaN for its correlations; SRRC are NaN
// when n <= dimensions + 1 or the rank regression is singular. The ranking's
// intervals come from `resamples` bootstrap resamples of the rows (fewer
// when kRankBootstrapBudget is exceeded; none below kRankBootstrapMinimum),
// drawn from a counter-based generator keyed by `seed`; each resample
// reuses the full sample's ranks (re-ranking a resample moves the measures
// far less than their sampling error). Throws std::invalid_argument for
// mismatched sizes, no inputs or a NaN value.
RankSensitivity rank_sensitivity(std::span<const double> inputs, std::size_t dimensions,
                                 std::span<const double> response, int resamples = 0, std::uint64_t seed = 0);

}  // namespace treedyn::analysis
