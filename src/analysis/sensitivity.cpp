#include "analysis/sensitivity.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "sampling/design.hpp"

namespace treedyn::ensemble {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Stream of counter_uniform reserved for the bootstrap's block draws, so they
// never coincide with a design's own streams for the same seed.
constexpr std::uint64_t kBootstrapStream = 7;

// Centred copy of `values` scaled to unit Euclidean norm; false (and the
// contents unspecified) when the values are constant, which has no scale.
// Unit norm rather than unit standard deviation: the regression coefficients
// are the same either way, and then Z^T Z is the correlation matrix.
bool standardise(std::span<const double> values, std::vector<double>& out) {
  const double n = static_cast<double>(values.size());
  const double mean = std::accumulate(values.begin(), values.end(), 0.0) / n;
  out.resize(values.size());
  double squares = 0.0;
  for (std::size_t k = 0; k < values.size(); ++k) {
    out[k] = values[k] - mean;
    squares += out[k] * out[k];
  }
  if (!(squares > 0.0)) return false;
  const double norm = std::sqrt(squares);
  for (double& v : out) v /= norm;
  return true;
}

// Pearson correlation of two equally long series; NaN when either is
// constant (or there are fewer than two values).
double pearson(std::span<const double> x, std::span<const double> y) {
  const std::size_t n = x.size();
  if (n < 2) return kNaN;
  const double mean_x = std::accumulate(x.begin(), x.end(), 0.0) / static_cast<double>(n);
  const double mean_y = std::accumulate(y.begin(), y.end(), 0.0) / static_cast<double>(n);
  double sxy = 0.0, sxx = 0.0, syy = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double dx = x[k] - mean_x, dy = y[k] - mean_y;
    sxy += dx * dy;
    sxx += dx * dx;
    syy += dy * dy;
  }
  if (!(sxx > 0.0) || !(syy > 0.0)) return kNaN;
  return sxy / std::sqrt(sxx * syy);
}

// Percentile p of `values` (sorted in place) by linear interpolation between
// order statistics at position (R - 1) p, "type 7" of Hyndman and Fan, the
// default of numpy and R. NaN if any value is NaN: a resample without a
// defined index leaves the interval undefined rather than silently narrower.
double percentile(std::vector<double>& values, double p) {
  if (values.empty() || std::any_of(values.begin(), values.end(), [](double v) { return std::isnan(v); }))
    return kNaN;
  std::sort(values.begin(), values.end());
  const double position = p * static_cast<double>(values.size() - 1);
  const auto below = static_cast<std::size_t>(std::floor(position));
  if (below + 1 >= values.size()) return values.back();
  const double fraction = position - static_cast<double>(below);
  return values[below] + fraction * (values[below + 1] - values[below]);
}

// Point estimates of Saltelli's design restricted to the blocks `blocks`
// (block j of the resample is block blocks[j] of the data; repeats allowed).
struct SaltelliEstimate {
  double variance = kNaN;
  std::vector<double> first, total;
};

SaltelliEstimate estimate(std::span<const double> f_a, std::span<const double> f_b,
                          std::span<const double> f_ab, std::size_t dimensions,
                          std::span<const std::size_t> blocks) {
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
    double first = 0.0, total = 0.0;
    for (const std::size_t j : blocks) {
      const double ab = f_ab[j * dimensions + i];
      // Saltelli 2010, Table 2 (b), with f(B) centred: the same expectation
      // (the mean of f(AB_i) - f(A) is zero), far less noise for a response
      // with a large offset (a position, an energy).
      first += (f_b[j] - mean) * (ab - f_a[j]);
      total += (f_a[j] - ab) * (f_a[j] - ab);  // Jansen 1999, Table 2 (f)
    }
    e.first[i] = first / static_cast<double>(n) / e.variance;
    e.total[i] = total / (2.0 * static_cast<double>(n)) / e.variance;
  }
  return e;
}

}  // namespace

std::vector<double> average_ranks(std::span<const double> values) {
  const std::size_t n = values.size();
  if (std::any_of(values.begin(), values.end(), [](double v) { return std::isnan(v); }))
    throw std::invalid_argument("average_ranks: NaN value (drop those rows first)");
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  // Stable, so equal values keep their input order (the ranks do not depend
  // on it, but the procedure is then fully specified).
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return values[a] < values[b]; });
  std::vector<double> ranks(n);
  for (std::size_t first = 0; first < n;) {
    std::size_t last = first;  // the run [first, last] of equal values
    while (last + 1 < n && values[order[last + 1]] == values[order[first]]) ++last;
    // Mean of the 1-based ranks first + 1 .. last + 1.
    const double rank = 0.5 * static_cast<double>(first + last) + 1.0;
    for (std::size_t k = first; k <= last; ++k) ranks[order[k]] = rank;
    first = last + 1;
  }
  return ranks;
}

RankSensitivity rank_sensitivity(std::span<const double> inputs, std::size_t dimensions,
                                 std::span<const double> response) {
  const std::size_t n = response.size();
  if (dimensions == 0) throw std::invalid_argument("rank_sensitivity: no inputs");
  if (inputs.size() != n * dimensions)
    throw std::invalid_argument("rank_sensitivity: inputs are not n rows x dimensions");

  RankSensitivity result;
  result.samples = n;
  result.spearman.assign(dimensions, kNaN);
  result.srrc.assign(dimensions, kNaN);
  result.r_squared = kNaN;

  const std::vector<double> response_ranks = average_ranks(response);
  std::vector<std::vector<double>> input_ranks(dimensions);
  std::vector<double> column(n);
  for (std::size_t i = 0; i < dimensions; ++i) {
    for (std::size_t k = 0; k < n; ++k) column[k] = inputs[k * dimensions + i];
    input_ranks[i] = average_ranks(column);
    result.spearman[i] = pearson(input_ranks[i], response_ranks);
  }

  // The rank regression needs more rows than parameters (d slopes plus the
  // intercept, here absorbed by centring) to leave a residual.
  if (n <= dimensions + 1) return result;

  // Least squares of the standardised response rank on the standardised input
  // ranks, by column-pivoted QR of the rank matrix itself: better conditioned
  // than the normal equations (squares the condition number), and its rank
  // reveals collinear or constant inputs.
  std::vector<double> standardised;
  Eigen::MatrixXd z(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(dimensions));
  for (std::size_t i = 0; i < dimensions; ++i) {
    if (!standardise(input_ranks[i], standardised)) return result;  // constant input: singular
    for (std::size_t k = 0; k < n; ++k)
      z(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(i)) = standardised[k];
  }
  if (!standardise(response_ranks, standardised)) return result;  // constant response
  const Eigen::VectorXd target = Eigen::Map<const Eigen::VectorXd>(standardised.data(),
                                                                   static_cast<Eigen::Index>(n));

  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(z);
  if (qr.rank() < static_cast<Eigen::Index>(dimensions)) return result;
  const Eigen::VectorXd coefficients = qr.solve(target);
  for (std::size_t i = 0; i < dimensions; ++i)
    result.srrc[i] = coefficients(static_cast<Eigen::Index>(i));
  // The target has unit norm, so 1 - |residual|^2 is the explained share.
  result.r_squared = 1.0 - (target - z * coefficients).squaredNorm();
  return result;
}

SobolIndices saltelli_indices(std::span<const double> f_a, std::span<const double> f_b,
                              std::span<const double> f_ab, std::size_t dimensions, int resamples,
                              std::uint64_t seed) {
  const std::size_t n = f_a.size();
  if (f_b.size() != n) throw std::invalid_argument("saltelli_indices: f_a and f_b differ in size");
  if (f_ab.size() != n * dimensions)
    throw std::invalid_argument("saltelli_indices: f_ab is not N rows x dimensions");

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
  if (resamples <= 0 || !(point.variance > 0.0)) return result;

  // Resample r draws block j as floor(u N), u from (seed, r, j): any rank can
  // reproduce resample r without the others.
  const auto count = static_cast<std::size_t>(resamples);
  std::vector<std::vector<double>> first(dimensions, std::vector<double>(count));
  std::vector<std::vector<double>> total(dimensions, std::vector<double>(count));
  for (std::size_t r = 0; r < count; ++r) {
    for (std::size_t j = 0; j < n; ++j) {
      const double u = counter_uniform(seed, r, j, kBootstrapStream);
      // u < 1, but u N may round up to N.
      blocks[j] = std::min(static_cast<std::size_t>(u * static_cast<double>(n)), n - 1);
    }
    const SaltelliEstimate e = estimate(f_a, f_b, f_ab, dimensions, blocks);
    for (std::size_t i = 0; i < dimensions; ++i) {
      first[i][r] = e.first[i];
      total[i][r] = e.total[i];
    }
  }
  for (std::size_t i = 0; i < dimensions; ++i) {
    result.first_ci[2 * i] = percentile(first[i], 0.025);
    result.first_ci[2 * i + 1] = percentile(first[i], 0.975);
    result.total_ci[2 * i] = percentile(total[i], 0.025);
    result.total_ci[2 * i + 1] = percentile(total[i], 0.975);
  }
  return result;
}

}  // namespace treedyn::ensemble
