// What one sample's trajectory is reduced to: per-column reductions over
// time (final, min, max and when they happen) and named responses, scalar
// functions of one column with an optional limit state. Pure functions of
// the trajectory and the output times.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "common/enum_names.hpp"

namespace treedyn {

// Per-sample reductions of every recorded column, stored in
// /samples/<reduction>/<quantity>.
enum class Reduction { final, min, max, argmin_time, argmax_time };
inline constexpr NameTable<Reduction, 5> kReductionNames{{{Reduction::final, "final"},
                                                          {Reduction::min, "min"},
                                                          {Reduction::max, "max"},
                                                          {Reduction::argmin_time, "argmin_time"},
                                                          {Reduction::argmax_time, "argmax_time"}}};
inline std::string_view name(Reduction r) { return name_in(kReductionNames, r); }

// Appends, for each reduction in `which` (in that order), one value per
// column of a times x columns trajectory (row-major). The time of a minimum
// or maximum is the first output time it is reached.
void reduce_columns(std::span<const double> trajectory, std::span<const double> times, std::size_t columns,
                    std::span<const Reduction> which, std::vector<double>& out);

// What reduce_columns works in: kept by a caller that reduces every sample,
// so that a sample allocates nothing once the first has sized it.
struct ReductionScratch {
  // Per column, [0] the minimum and [1] the maximum, and the row where each
  // is first reached (a double, exact below 2^53 rows, so that the search
  // selects values and rows with the same mask).
  std::vector<double> value[2], row[2];
};
void reduce_columns(std::span<const double> trajectory, std::span<const double> times, std::size_t columns,
                    std::span<const Reduction> which, std::vector<double>& out, ReductionScratch& scratch);

struct Response {
  enum class Reduce { final, min, max, mean, rms, at_time, first_time_above, first_time_below };
  enum class FailIf { none, above, below };

  std::string name;
  std::string quantity, column;  // as in the file, e.g. "point_position", "tip.z"
  std::size_t column_index = 0;  // in the flat row of recorded columns
  std::string units;             // of the value: the column's, or "s" for the first_time_*
  Reduce reduce = Reduce::max;
  double time = 0.0;       // at_time
  double threshold = 0.0;  // first_time_above / first_time_below
  FailIf fail_if = FailIf::none;
  double limit = 0.0;

  bool has_limit() const { return fail_if != FailIf::none; }
  // The limit state: value beyond the limit (strictly). NaN never exceeds.
  bool exceeds(double value) const {
    return fail_if == FailIf::above ? value > limit : fail_if == FailIf::below && value < limit;
  }
};

inline constexpr NameTable<Response::Reduce, 8> kResponseReduceNames{
    {{Response::Reduce::final, "final"},
     {Response::Reduce::min, "min"},
     {Response::Reduce::max, "max"},
     {Response::Reduce::mean, "mean"},
     {Response::Reduce::rms, "rms"},
     {Response::Reduce::at_time, "at_time"},
     {Response::Reduce::first_time_above, "first_time_above"},
     {Response::Reduce::first_time_below, "first_time_below"}}};
inline std::string_view name(Response::Reduce r) { return name_in(kResponseReduceNames, r); }

// The side of the limit a response fails on, as the job and the files say it.
// (none: "", no limit).
inline constexpr NameTable<Response::FailIf, 2> kFailIfNames{
    {{Response::FailIf::above, "above"}, {Response::FailIf::below, "below"}}};
inline std::string_view name(Response::FailIf f) {
  return f == Response::FailIf::none ? std::string_view{} : name_in(kFailIfNames, f);
}

// The response's value on one trajectory:
//   final, min, max       the column's value at the last output time, its extremes;
//   mean, rms             the mean and root mean square over the output times
//                         (every output time weighs the same);
//   at_time               linear interpolation between the two output times around `time`
//                         (exact at an output time);
//   first_time_above/below  the first time the column is above / below `threshold`:
//                         linear interpolation inside the output step where it first
//                         crosses, the first output time if it starts beyond, +inf if never.
double evaluate(const Response& response, std::span<const double> trajectory, std::span<const double> times,
                std::size_t columns);

}  // namespace treedyn
