#include "output/response.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>

namespace treedyn {

namespace {

// Two doubles as one value (GCC's and Clang's vector extension: SSE2 on
// x86-64, plain scalars where a target has no vectors). GCC 12 does not
// vectorise the selects below on its own ("control flow in loop").
using Lanes = double __attribute__((vector_size(16)));

// Columns c .. c + sizeof(T) / sizeof(double) - 1 of one row against the
// extremes so far: T is double or Lanes. Strict comparisons keep the
// first row of a tie; a NaN compares false, so it is never an extreme.
template <class T>
void keep_extremes(const double* row, std::size_t c, const T& at, ReductionScratch& s) {
  T v, lo, hi, lo_at, hi_at;
  std::memcpy(&v, row + c, sizeof v);
  std::memcpy(&lo, s.value[0].data() + c, sizeof v);
  std::memcpy(&hi, s.value[1].data() + c, sizeof v);
  std::memcpy(&lo_at, s.row[0].data() + c, sizeof v);
  std::memcpy(&hi_at, s.row[1].data() + c, sizeof v);
  const auto below = v<lo, above = v> hi;
  lo = below ? v : lo;
  lo_at = below ? at : lo_at;
  hi = above ? v : hi;
  hi_at = above ? at : hi_at;
  std::memcpy(s.value[0].data() + c, &lo, sizeof v);
  std::memcpy(s.value[1].data() + c, &hi, sizeof v);
  std::memcpy(s.row[0].data() + c, &lo_at, sizeof v);
  std::memcpy(s.row[1].data() + c, &hi_at, sizeof v);
}

// For every column, the first output time at which it is smallest and the
// first at which it is largest: one pass over the rows in memory order,
// branch-free, two columns at a time.
void first_extremes(std::span<const double> trajectory, std::size_t times, std::size_t columns,
                    ReductionScratch& scratch) {
  for (int side = 0; side < 2; ++side) {
    scratch.value[side].assign(trajectory.begin(), trajectory.begin() + static_cast<std::ptrdiff_t>(columns));
    scratch.row[side].assign(columns, 0.0);
  }
  constexpr std::size_t lanes = sizeof(Lanes) / sizeof(double);
  const std::size_t paired = columns - columns % lanes;
  for (std::size_t k = 1; k < times; ++k) {
    const double* row = trajectory.data() + k * columns;
    const auto at = static_cast<double>(k);
    for (std::size_t c = 0; c < paired; c += lanes) keep_extremes(row, c, Lanes{} + at, scratch);
    for (std::size_t c = paired; c < columns; ++c) keep_extremes(row, c, at, scratch);
  }
}

}  // namespace

void reduce_columns(std::span<const double> trajectory, std::span<const double> times, std::size_t columns,
                    std::span<const Reduction> which, std::vector<double>& out) {
  ReductionScratch scratch;
  reduce_columns(trajectory, times, columns, which, out, scratch);
}

void reduce_columns(std::span<const double> trajectory, std::span<const double> times, std::size_t columns,
                    std::span<const Reduction> which, std::vector<double>& out, ReductionScratch& scratch) {
  const std::size_t T = times.size();
  bool searched = false;  // minima and maxima: one pass finds both
  for (Reduction r : which) {
    if (r == Reduction::final) {
      out.insert(out.end(), trajectory.begin() + static_cast<std::ptrdiff_t>((T - 1) * columns),
                 trajectory.begin() + static_cast<std::ptrdiff_t>(T * columns));
      continue;
    }
    if (!searched) first_extremes(trajectory, T, columns, scratch);
    searched = true;
    const int side = r == Reduction::min || r == Reduction::argmin_time ? 0 : 1;
    const bool value = r == Reduction::min || r == Reduction::max;
    for (std::size_t c = 0; c < columns; ++c)
      out.push_back(value ? scratch.value[side][c] : times[static_cast<std::size_t>(scratch.row[side][c])]);
  }
}

namespace {

// One column of a trajectory read in place (rows of `columns` values, one
// per output time): x[k] is its value at output time k. Read through this
// instead of a copy, a response allocates nothing per sample.
struct ColumnView {
  const double* first;
  std::size_t stride, size;
  double operator[](std::size_t k) const { return first[k * stride]; }
  double back() const { return (*this)[size - 1]; }
};

// The first smallest (below) or largest value, as std::min_element and
// std::max_element find it: a NaN is never taken over the value before it.
double first_extreme(ColumnView x, bool below) {
  double best = x[0];
  for (std::size_t k = 1; k < x.size; ++k)
    if (below ? x[k] < best : best < x[k]) best = x[k];
  return best;
}

double first_time_beyond(ColumnView x, std::span<const double> times, double threshold, bool above) {
  auto beyond = [&](double v) { return above ? v > threshold : v < threshold; };
  if (beyond(x[0])) return times[0];
  for (std::size_t k = 1; k < x.size; ++k) {
    if (!beyond(x[k])) continue;
    // x[k-1] is not beyond and x[k] is: the crossing lies in (t[k-1], t[k]].
    const double fraction = (threshold - x[k - 1]) / (x[k] - x[k - 1]);
    return times[k - 1] + std::clamp(fraction, 0.0, 1.0) * (times[k] - times[k - 1]);
  }
  return std::numeric_limits<double>::infinity();
}

double at_time(ColumnView x, std::span<const double> times, double t) {
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
  const ColumnView x{trajectory.data() + r.column_index, columns, times.size()};
  using Reduce = Response::Reduce;
  switch (r.reduce) {
    case Reduce::final:
      return x.back();
    case Reduce::min:
      return first_extreme(x, true);
    case Reduce::max:
      return first_extreme(x, false);
    case Reduce::mean: {
      double sum = 0.0;
      for (std::size_t k = 0; k < x.size; ++k) sum += x[k];
      return sum / static_cast<double>(x.size);
    }
    case Reduce::rms: {
      double sum = 0.0;
      for (std::size_t k = 0; k < x.size; ++k) sum += x[k] * x[k];
      return std::sqrt(sum / static_cast<double>(x.size));
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

}  // namespace treedyn
