#include "analysis/sensitivity.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "analysis/ranking.hpp"
#include "sampling/design.hpp"

namespace treedyn::analysis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

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
      const double u = sampling::counter_uniform(seed, static_cast<std::uint64_t>(r), static_cast<std::uint64_t>(k),
                                                 kRowBootstrapStream);
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

}  // namespace treedyn::analysis
