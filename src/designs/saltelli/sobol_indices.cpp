#include "designs/saltelli/sobol_indices.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "sampling/design.hpp"

namespace treedyn::designs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Stream of sampling::counter_uniform reserved for the bootstrap's block draws, so they
// never coincide with a design's own streams for the same seed.
constexpr std::uint64_t kBootstrapStream = 7;

// Point estimates of Saltelli's design restricted to the blocks `blocks`
// (block j of the resample is block blocks[j] of the data; repeats allowed).
struct SaltelliEstimate {
  double variance = kNaN;
  std::vector<double> first, total;
};

// Janon et al. 2014's total index of unit i: 1 minus their closed index of
// every other unit, estimated from the pair (f(A), f(AB_i)) that shares all
// inputs but i. With m_i the pair's mean, 1 - C / D (C the pair's
// covariance, D its variance, both about m_i) is the ratio below, computed
// from deviations so that a large offset does not cancel. A pair without
// spread has no effect of i to show: 0.
double janon_total(std::span<const double> f_a, std::span<const double> f_ab, std::size_t dimensions, std::size_t i,
                   std::span<const std::size_t> blocks, double pair_mean) {
  double differences = 0.0, spread = 0.0;
  for (const std::size_t j : blocks) {
    const double a = f_a[j], ab = f_ab[j * dimensions + i];
    differences += (a - ab) * (a - ab);
    spread += (a - pair_mean) * (a - pair_mean) + (ab - pair_mean) * (ab - pair_mean);
  }
  return differences == 0.0 ? 0.0 : differences / spread;
}

SaltelliEstimate estimate(std::span<const double> f_a, std::span<const double> f_b, std::span<const double> f_ab,
                          std::size_t dimensions, std::span<const std::size_t> blocks) {
  const std::size_t n = blocks.size();
  SaltelliEstimate e;
  e.first.assign(dimensions, kNaN);
  e.total.assign(dimensions, kNaN);
  if (n == 0) return e;

  // V: the population variance, 1/(2N) sum (f - mean)^2, over the 2N values
  // of A and B (as SALib does). The 1/(2N - 1) alternative changes the
  // indices by a factor 1 - 1/(2N), far below their sampling error.
  // Two passes (mean, then squares) avoid the cancellation of sum f^2 - ...
  double sum = 0.0;
  for (const std::size_t j : blocks) sum += f_a[j] + f_b[j];
  const double mean = sum / (2.0 * static_cast<double>(n));
  double squares = 0.0;
  for (const std::size_t j : blocks) {
    const double da = f_a[j] - mean, db = f_b[j] - mean;
    squares += da * da + db * db;
  }
  e.variance = squares / (2.0 * static_cast<double>(n));
  if (!(e.variance > 0.0)) return e;  // zero (or NaN) variance: no indices

  for (std::size_t i = 0; i < dimensions; ++i) {
    double first = 0.0, pair_sum = 0.0;
    for (const std::size_t j : blocks) {
      const double ab = f_ab[j * dimensions + i];
      // Saltelli 2010, Table 2 (b), with f(B) centred: the same expectation
      // (the mean of f(AB_i) - f(A) is zero), far less noise for a response
      // with a large offset (a position, an energy).
      first += (f_b[j] - mean) * (ab - f_a[j]);
      pair_sum += f_a[j] + ab;
    }
    e.first[i] = first / static_cast<double>(n) / e.variance;
    e.total[i] = janon_total(f_a, f_ab, dimensions, i, blocks, pair_sum / (2.0 * static_cast<double>(n)));
  }
  return e;
}

}  // namespace

SobolIndices saltelli_indices(std::span<const double> f_a, std::span<const double> f_b, std::span<const double> f_ab,
                              std::size_t dimensions, int resamples, std::uint64_t seed) {
  const std::size_t n = f_a.size();
  if (f_b.size() != n) throw std::invalid_argument("saltelli_indices: f_a and f_b differ in size");
  if (f_ab.size() != n * dimensions) throw std::invalid_argument("saltelli_indices: f_ab is not N rows x dimensions");

  std::vector<std::size_t> blocks(n);
  std::iota(blocks.begin(), blocks.end(), std::size_t{0});
  const SaltelliEstimate point = estimate(f_a, f_b, f_ab, dimensions, blocks);

  SobolIndices result;
  result.first = point.first;
  result.total = point.total;
  result.variance = point.variance;
  result.base_samples = n;
  result.first_ci.assign(2 * dimensions, kNaN);
  result.total_ci.assign(2 * dimensions, kNaN);
  result.ranking = analysis::rank_units(result.total, {}, n);
  if (resamples <= 0 || !(point.variance > 0.0)) return result;

  // Resample r draws block j as floor(u N), u from (seed, r, j): any rank can
  // reproduce resample r without the others.
  const auto count = static_cast<std::size_t>(resamples);
  std::vector<double> first(count * dimensions), total(count * dimensions);  // resample-major
  for (std::size_t r = 0; r < count; ++r) {
    for (std::size_t j = 0; j < n; ++j) {
      const double u = sampling::counter_uniform(seed, r, j, kBootstrapStream);
      // u < 1, but u N may round up to N.
      blocks[j] = std::min(static_cast<std::size_t>(u * static_cast<double>(n)), n - 1);
    }
    const SaltelliEstimate e = estimate(f_a, f_b, f_ab, dimensions, blocks);
    std::copy(e.first.begin(), e.first.end(), first.begin() + static_cast<std::ptrdiff_t>(r * dimensions));
    std::copy(e.total.begin(), e.total.end(), total.begin() + static_cast<std::ptrdiff_t>(r * dimensions));
  }
  analysis::percentile_intervals(first, dimensions, result.first_ci);
  analysis::percentile_intervals(total, dimensions, result.total_ci);
  result.ranking = analysis::rank_units(result.total, total, n);
  return result;
}

}  // namespace treedyn::designs
