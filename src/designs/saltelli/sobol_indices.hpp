// Sobol' indices from Saltelli's design: first-order and total indices of
// each unit with bootstrap intervals, from the responses of the A, B and
// AB_i runs of each base point. A pure function of its arguments, so the
// same records give the same bits on any number of ranks.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "analysis/ranking.hpp"

namespace treedyn::designs {

struct SobolIndices {
  std::vector<double> first;     // per input: first-order index (Saltelli 2010)
  std::vector<double> total;     // per input: total index (Janon et al. 2014)
  std::vector<double> first_ci;  // per input: 95 % bootstrap interval, low and high (2 per input)
  std::vector<double> total_ci;
  double variance = 0.0;         // of f over A and B together (the first-order denominator)
  std::size_t base_samples = 0;  // N, the blocks used
  analysis::Ranking ranking;     // by the total index
};

// With m and V the mean and the population variance (1/2N) of f over the 2N
// values of A and B:
//   S_i  = (1/N) sum_j (f(B)_j - m) (f(AB_i)_j - f(A)_j) / V
// (Saltelli 2010, Table 2 (b), with f(B) centred: the same expectation,
// less noise when f has a large offset), and
//   ST_i = sum_j (f(A)_j - f(AB_i)_j)^2 / sum_j ((f(A)_j - m_i)^2 + (f(AB_i)_j - m_i)^2),
// m_i the mean of the 2N values f(A), f(AB_i): Janon et al. 2014's
// estimator of the closed index of all inputs but i, taken from 1 (Jansen's
// numerator over the variance of the pair it is computed from). Of the
// published estimators compared on Ishigami's and Sobol's g function over
// 200 design seeds (tests/designs/sobol_estimator_test.cpp, docs/design.md), these
// two have the smallest error at N = 16, 64 and 256. Intervals:
// first_ci[2i], [2i+1] = low, high. The bootstrap treats the blocks as
// independent draws; with scrambled Sobol points the actual error is
// usually well inside the interval.
// f_a, f_b: N values; f_ab: N rows x `dimensions`, row j column i = f(AB_i)_j.
// The intervals are percentile intervals of `resamples` bootstrap
// resamplings of the N blocks, drawn from a counter-based generator keyed
// by `seed` (reproducible). Zero variance gives NaN indices.
SobolIndices saltelli_indices(std::span<const double> f_a, std::span<const double> f_b, std::span<const double> f_ab,
                              std::size_t dimensions, int resamples, std::uint64_t seed);

}  // namespace treedyn::designs
