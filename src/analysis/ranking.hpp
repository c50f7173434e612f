// Which inputs the data tell apart: a ranking of the inputs (or groups) by a
// sensitivity measure that states an order only where the bootstrap
// separates two neighbours, and otherwise how many more samples would.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace treedyn::analysis {

inline constexpr double kZ95 = 1.959963984540054;  // the 97.5 % standard normal quantile

struct Ranking {
  // The units, largest measure first; units with a NaN measure last, in
  // index order.
  std::vector<std::size_t> order;
  // Per neighbour pair k = (order[k], order[k+1]): the 95 % percentile
  // interval (low, high at 2k, 2k + 1) of the difference of their measures
  // over the bootstrap resamples. The pair is told apart when low > 0.
  std::vector<double> difference_ci;
  // Per neighbour pair: about how many samples (base points for Saltelli,
  // runs otherwise) would tell it apart four times in five,
  // N ((1.96 + 0.84) sd / d)^2 with d the difference and sd its bootstrap
  // standard deviation at N (the error falls like 1 / sqrt(N)). Rough: d is
  // itself uncertain. NaN once told apart or when undefined (a NaN
  // measure), +inf when the two are equal (nothing to separate).
  std::vector<double> needed;
  std::size_t resamples = 0;  // bootstrap resamples behind the intervals

  std::size_t pairs() const { return needed.size(); }
  bool told_apart(std::size_t k) const { return difference_ci[2 * k] > 0.0; }
};

// `point`: the measure of each of U units at sample size n; `replicates`:
// R rows of U, the measure on each bootstrap resample (row-major). Empty
// replicates give the order alone (every pair not told apart, needed NaN).
Ranking rank_units(std::span<const double> point, std::span<const double> replicates, std::size_t n);

// Percentile p of `values` (sorted in place) by linear interpolation between
// order statistics at (R - 1) p, "type 7" of Hyndman and Fan (numpy's and
// R's default); NaN when empty or when any value is NaN (a resample without
// a defined measure leaves the interval undefined, not silently narrower).
double percentile(std::vector<double>& values, double p);

// The 95 % percentile interval of each of the `units` columns of the
// resample-major `replicates` into `out` (low, high per unit; out has 2
// units values).
void percentile_intervals(std::span<const double> replicates, std::size_t units, std::vector<double>& out);

}  // namespace treedyn::analysis
