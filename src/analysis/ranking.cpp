#include "analysis/ranking.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace treedyn::analysis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Mean and standard deviation (n - 1) of `values`, NaN-free by the caller.
double standard_deviation(const std::vector<double>& values) {
  if (values.size() < 2) return kNaN;
  const double mean = std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
  double squares = 0.0;
  for (const double v : values) squares += (v - mean) * (v - mean);
  return std::sqrt(squares / static_cast<double>(values.size() - 1));
}

// The samples at which a difference d (bootstrap sd at n) clears its 95 %
// interval four times in five: d = (1.96 + 0.84) sd, with sd falling like
// 1 / sqrt(n). The 80 % power is the usual sample-size rule; at 50 % (1.96
// alone) the estimates made where a pair is not yet told apart came out
// about half the N that then told it apart (tests/analysis/ranking_test.cpp).
double samples_to_separate(double d, double sd, std::size_t n) {
  constexpr double kZ80Power = 0.8416212335729143;  // the 80 % standard normal quantile
  if (!std::isfinite(d) || !std::isfinite(sd)) return kNaN;
  if (!(d > 0.0)) return std::numeric_limits<double>::infinity();
  const double ratio = (kZ95 + kZ80Power) * sd / d;
  return std::ceil(static_cast<double>(n) * ratio * ratio);
}

}  // namespace

double percentile(std::vector<double>& values, double p) {
  if (values.empty() || std::any_of(values.begin(), values.end(), [](double v) { return std::isnan(v); })) return kNaN;
  std::sort(values.begin(), values.end());
  const double position = p * static_cast<double>(values.size() - 1);
  const auto below = static_cast<std::size_t>(std::floor(position));
  if (below + 1 >= values.size()) return values.back();
  const double fraction = position - static_cast<double>(below);
  return values[below] + fraction * (values[below + 1] - values[below]);
}

Ranking rank_units(std::span<const double> point, std::span<const double> replicates, std::size_t n) {
  const std::size_t units = point.size();
  Ranking ranking;
  ranking.order.resize(units);
  std::iota(ranking.order.begin(), ranking.order.end(), std::size_t{0});
  // Stable, NaN last: the order is fully specified whatever the values.
  std::stable_sort(ranking.order.begin(), ranking.order.end(), [&](std::size_t a, std::size_t b) {
    if (std::isnan(point[b])) return !std::isnan(point[a]);
    return !std::isnan(point[a]) && point[a] > point[b];
  });
  const std::size_t pairs = units > 0 ? units - 1 : 0;
  ranking.difference_ci.assign(2 * pairs, kNaN);
  ranking.needed.assign(pairs, kNaN);
  const std::size_t resamples = units > 0 ? replicates.size() / units : 0;
  ranking.resamples = resamples;
  if (resamples == 0) return ranking;

  std::vector<double> differences(resamples);
  for (std::size_t k = 0; k < pairs; ++k) {
    const std::size_t a = ranking.order[k], b = ranking.order[k + 1];
    for (std::size_t r = 0; r < resamples; ++r) differences[r] = replicates[r * units + a] - replicates[r * units + b];
    const double sd = std::any_of(differences.begin(), differences.end(), [](double v) { return std::isnan(v); })
                          ? kNaN
                          : standard_deviation(differences);
    ranking.difference_ci[2 * k] = percentile(differences, 0.025);
    ranking.difference_ci[2 * k + 1] = percentile(differences, 0.975);
    if (!ranking.told_apart(k)) ranking.needed[k] = samples_to_separate(point[a] - point[b], sd, n);
  }
  return ranking;
}

void percentile_intervals(std::span<const double> replicates, std::size_t units, std::vector<double>& out) {
  const std::size_t resamples = replicates.size() / units;
  std::vector<double> column(resamples);
  for (std::size_t i = 0; i < units; ++i) {
    for (std::size_t r = 0; r < resamples; ++r) column[r] = replicates[r * units + i];
    out[2 * i] = percentile(column, 0.025);
    out[2 * i + 1] = percentile(column, 0.975);
  }
}

}  // namespace treedyn::analysis
