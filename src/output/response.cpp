#include "output/response.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

namespace treedyn::ensemble {

namespace {

// For every column, the first output time at which it is smallest
// (`minimum`) or largest: one pass over the rows in memory order, keeping
// each column's best value beside its row (no dependent load per element;
// the comparison is hoisted, so the compiler vectorises the row's loop).
template <class Better>
void first_extremes(std::span<const double> trajectory, std::size_t times, std::size_t columns, Better better,
                    std::vector<std::size_t>& best, std::vector<double>& value) {
  best.assign(columns, 0);
  value.assign(trajectory.begin(), trajectory.begin() + static_cast<std::ptrdiff_t>(columns));
  for (std::size_t k = 1; k < times; ++k) {
    const double* row = trajectory.data() + k * columns;
    for (std::size_t c = 0; c < columns; ++c) {
      const bool b = better(row[c], value[c]);
      value[c] = b ? row[c] : value[c];
      best[c] = b ? k : best[c];
    }
  }
}

void first_extremes(std::span<const double> trajectory, std::size_t times, std::size_t columns, bool minimum,
                    std::vector<std::size_t>& best, std::vector<double>& value) {
  if (minimum)
    first_extremes(trajectory, times, columns, std::less<>{}, best, value);
  else
    first_extremes(trajectory, times, columns, std::greater<>{}, best, value);
}

}  // namespace

void reduce_columns(std::span<const double> trajectory, std::span<const double> times,
                    std::size_t columns, std::span<const Reduction> which, std::vector<double>& out) {
  ReductionScratch scratch;
  reduce_columns(trajectory, times, columns, which, out, scratch);
}

void reduce_columns(std::span<const double> trajectory, std::span<const double> times,
                    std::size_t columns, std::span<const Reduction> which, std::vector<double>& out,
                    ReductionScratch& scratch) {
  const std::size_t T = times.size();
  bool found[2] = {false, false};  // minima, maxima: each searched once
  for (Reduction r : which) {
    if (r == Reduction::final) {
      out.insert(out.end(), trajectory.begin() + static_cast<std::ptrdiff_t>((T - 1) * columns),
                 trajectory.begin() + static_cast<std::ptrdiff_t>(T * columns));
      continue;
    }
    const bool minimum = r == Reduction::min || r == Reduction::argmin_time;
    const int slot = minimum ? 0 : 1;
    std::vector<std::size_t>& at = scratch.best[slot];
    if (!found[slot]) first_extremes(trajectory, T, columns, minimum, at, scratch.value);
    found[slot] = true;
    const bool value = r == Reduction::min || r == Reduction::max;
    for (std::size_t c = 0; c < columns; ++c) out.push_back(value ? trajectory[at[c] * columns + c] : times[at[c]]);
  }
}

namespace {

double first_time_beyond(std::span<const double> x, std::span<const double> times, double threshold,
                         bool above) {
  auto beyond = [&](double v) { return above ? v > threshold : v < threshold; };
  if (beyond(x[0])) return times[0];
  for (std::size_t k = 1; k < x.size(); ++k) {
    if (!beyond(x[k])) continue;
    // x[k-1] is not beyond and x[k] is: the crossing lies in (t[k-1], t[k]].
    const double fraction = (threshold - x[k - 1]) / (x[k] - x[k - 1]);
    return times[k - 1] + std::clamp(fraction, 0.0, 1.0) * (times[k] - times[k - 1]);
  }
  return std::numeric_limits<double>::infinity();
}

double at_time(std::span<const double> x, std::span<const double> times, double t) {
  const auto upper = std::lower_bound(times.begin(), times.end(), t);
  if (upper == times.end()) return x.back();  // only within rounding of the end (checked on reading)
  const auto k = static_cast<std::size_t>(upper - times.begin());
  if (*upper == t || k == 0) return x[k];
  const double fraction = (t - times[k - 1]) / (times[k] - times[k - 1]);
  return x[k - 1] + fraction * (x[k] - x[k - 1]);
}

}  // namespace

double evaluate(const Response& r, std::span<const double> trajectory, std::span<const double> times,
                std::size_t columns) {
  std::vector<double> x(times.size());
  for (std::size_t k = 0; k < times.size(); ++k) x[k] = trajectory[k * columns + r.column_index];
  using Reduce = Response::Reduce;
  switch (r.reduce) {
    case Reduce::final:
      return x.back();
    case Reduce::min:
      return *std::min_element(x.begin(), x.end());
    case Reduce::max:
      return *std::max_element(x.begin(), x.end());
    case Reduce::mean: {
      double sum = 0.0;
      for (double v : x) sum += v;
      return sum / static_cast<double>(x.size());
    }
    case Reduce::rms: {
      double sum = 0.0;
      for (double v : x) sum += v * v;
      return std::sqrt(sum / static_cast<double>(x.size()));
    }
    case Reduce::at_time:
      return at_time(x, times, r.time);
    case Reduce::first_time_above:
      return first_time_beyond(x, times, r.threshold, true);
    case Reduce::first_time_below:
      return first_time_beyond(x, times, r.threshold, false);
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace treedyn::ensemble
