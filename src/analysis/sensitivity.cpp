#include "analysis/sensitivity.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "analysis/ranking.hpp"
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

// Stream of counter_uniform for the rank measures' row bootstrap.
constexpr std::uint64_t kRowBootstrapStream = 8;

// n rows x (D + 1) columns: the average ranks of each input, then of the
// response.
Eigen::MatrixXd rank_matrix(std::span<const double> inputs, std::size_t dimensions, std::span<const double> response) {
  const std::size_t n = response.size();
  Eigen::MatrixXd ranks(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(dimensions + 1));
  std::vector<double> column(n);
  for (std::size_t i = 0; i <= dimensions; ++i) {
    for (std::size_t k = 0; k < n; ++k) column[k] = i < dimensions ? inputs[k * dimensions + i] : response[k];
    const std::vector<double> r = average_ranks(column);
    ranks.col(static_cast<Eigen::Index>(i)) = Eigen::Map<const Eigen::VectorXd>(r.data(), static_cast<Eigen::Index>(n));
  }
  return ranks;
}

std::span<const double> column_of(const Eigen::MatrixXd& m, Eigen::Index c) {
  return {m.col(c).data(), static_cast<std::size_t>(m.rows())};
}

// Least squares of the standardised response rank on the standardised input
// ranks (the last column on the others), into srrc and r_squared, by
// column-pivoted QR of the rank matrix itself: better conditioned than the
// normal equations (squares the condition number), and its rank reveals
// collinear or constant inputs. Needs more rows than parameters (D slopes
// plus the intercept, absorbed by centring) to leave a residual.
void rank_regression(const Eigen::MatrixXd& ranks, RankSensitivity& result) {
  const auto n = static_cast<std::size_t>(ranks.rows());
  const Eigen::Index dimensions = ranks.cols() - 1;
  if (n <= static_cast<std::size_t>(dimensions) + 1) return;
  std::vector<double> standardised;
  Eigen::MatrixXd z(ranks.rows(), dimensions);
  for (Eigen::Index i = 0; i < dimensions; ++i) {
    if (!standardise(column_of(ranks, i), standardised)) return;  // constant input: singular
    z.col(i) = Eigen::Map<const Eigen::VectorXd>(standardised.data(), ranks.rows());
  }
  if (!standardise(column_of(ranks, dimensions), standardised)) return;  // constant response
  const Eigen::VectorXd target = Eigen::Map<const Eigen::VectorXd>(standardised.data(), ranks.rows());
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(z);
  if (qr.rank() < dimensions) return;
  const Eigen::VectorXd coefficients = qr.solve(target);
  for (Eigen::Index i = 0; i < dimensions; ++i) result.srrc[static_cast<std::size_t>(i)] = coefficients(i);
  // The target has unit norm, so 1 - |residual|^2 is the explained share.
  result.r_squared = 1.0 - (target - z * coefficients).squaredNorm();
}

// The ranking measure (|SRRC| or |Spearman|) on `resamples` bootstrap
// resamples of the rows, resample-major. Each resample is a weighted
// covariance matrix C of the rank columns (weight: how often the row was
// drawn): Spearman_i = C_iy / sqrt(C_ii C_yy); the SRRC solve C_xx b = C_xy,
// standardised by sqrt(C_ii / C_yy). A resample where they are undefined
// (a constant column, a singular C_xx) gives NaN.
std::vector<double> rank_replicates(const Eigen::MatrixXd& ranks, bool srrc, int resamples, std::uint64_t seed) {
  const Eigen::Index n = ranks.rows(), dimensions = ranks.cols() - 1;
  std::vector<double> out(static_cast<std::size_t>(resamples) * static_cast<std::size_t>(dimensions), kNaN);
  Eigen::VectorXd weight(n);
  for (int r = 0; r < resamples; ++r) {
    weight.setZero();
    for (Eigen::Index k = 0; k < n; ++k) {
      const double u =
          counter_uniform(seed, static_cast<std::uint64_t>(r), static_cast<std::uint64_t>(k), kRowBootstrapStream);
      weight(std::min<Eigen::Index>(static_cast<Eigen::Index>(u * static_cast<double>(n)), n - 1)) += 1.0;
    }
    const Eigen::RowVectorXd mean = (weight.transpose() * ranks) / static_cast<double>(n);
    const Eigen::MatrixXd centred = ranks.rowwise() - mean;
    const Eigen::MatrixXd c = centred.transpose() * (centred.array().colwise() * weight.array()).matrix();
    double* row = out.data() + static_cast<std::size_t>(r) * static_cast<std::size_t>(dimensions);
    const double c_yy = c(dimensions, dimensions);
    if (!(c_yy > 0.0)) continue;
    if (!srrc) {
      for (Eigen::Index i = 0; i < dimensions; ++i)
        if (c(i, i) > 0.0) row[i] = std::abs(c(i, dimensions) / std::sqrt(c(i, i) * c_yy));
      continue;
    }
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(c.topLeftCorner(dimensions, dimensions));
    if (qr.rank() < dimensions) continue;
    const Eigen::VectorXd b = qr.solve(c.topRightCorner(dimensions, 1));
    for (Eigen::Index i = 0; i < dimensions; ++i) row[i] = std::abs(b(i) * std::sqrt(c(i, i) / c_yy));
  }
  return out;
}

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

std::vector<double> average_ranks(std::span<const double> values) {
  const std::size_t n = values.size();
  if (std::any_of(values.begin(), values.end(), [](double v) { return std::isnan(v); }))
    throw std::invalid_argument("average_ranks: NaN value (drop those rows first)");
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  // Stable, so equal values keep their input order (the ranks do not depend
  // on it, but the procedure is then fully specified).
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return values[a] < values[b]; });
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
                                 std::span<const double> response, int resamples, std::uint64_t seed) {
  const std::size_t n = response.size();
  if (dimensions == 0) throw std::invalid_argument("rank_sensitivity: no inputs");
  if (inputs.size() != n * dimensions)
    throw std::invalid_argument("rank_sensitivity: inputs are not n rows x dimensions");

  RankSensitivity result;
  result.samples = n;
  result.spearman.assign(dimensions, kNaN);
  result.srrc.assign(dimensions, kNaN);
  result.r_squared = kNaN;

  const Eigen::MatrixXd ranks = rank_matrix(inputs, dimensions, response);
  const auto response_column = static_cast<Eigen::Index>(dimensions);
  for (std::size_t i = 0; i < dimensions; ++i)
    result.spearman[i] = pearson(column_of(ranks, static_cast<Eigen::Index>(i)), column_of(ranks, response_column));
  rank_regression(ranks, result);

  result.ranked_by_srrc =
      std::all_of(result.srrc.begin(), result.srrc.end(), [](double v) { return std::isfinite(v); });
  std::vector<double> point(dimensions);
  for (std::size_t i = 0; i < dimensions; ++i)
    point[i] = std::abs(result.ranked_by_srrc ? result.srrc[i] : result.spearman[i]);
  const int affordable = static_cast<int>(std::min<double>(
      resamples, kRankBootstrapBudget /
                     (0.5 * static_cast<double>(n) * static_cast<double>((dimensions + 1) * (dimensions + 1)))));
  const std::vector<double> replicates = n >= 2 && affordable >= kRankBootstrapMinimum
                                             ? rank_replicates(ranks, result.ranked_by_srrc, affordable, seed)
                                             : std::vector<double>{};
  result.ranking = rank_units(point, replicates, n);
  result.measure_ci.assign(2 * dimensions, kNaN);
  if (!replicates.empty()) percentile_intervals(replicates, dimensions, result.measure_ci);
  return result;
}

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
  result.ranking = rank_units(result.total, {}, n);
  if (resamples <= 0 || !(point.variance > 0.0)) return result;

  // Resample r draws block j as floor(u N), u from (seed, r, j): any rank can
  // reproduce resample r without the others.
  const auto count = static_cast<std::size_t>(resamples);
  std::vector<double> first(count * dimensions), total(count * dimensions);  // resample-major
  for (std::size_t r = 0; r < count; ++r) {
    for (std::size_t j = 0; j < n; ++j) {
      const double u = counter_uniform(seed, r, j, kBootstrapStream);
      // u < 1, but u N may round up to N.
      blocks[j] = std::min(static_cast<std::size_t>(u * static_cast<double>(n)), n - 1);
    }
    const SaltelliEstimate e = estimate(f_a, f_b, f_ab, dimensions, blocks);
    std::copy(e.first.begin(), e.first.end(), first.begin() + static_cast<std::ptrdiff_t>(r * dimensions));
    std::copy(e.total.begin(), e.total.end(), total.begin() + static_cast<std::ptrdiff_t>(r * dimensions));
  }
  percentile_intervals(first, dimensions, result.first_ci);
  percentile_intervals(total, dimensions, result.total_ci);
  result.ranking = rank_units(result.total, total, n);
  return result;
}

}  // namespace treedyn::ensemble
