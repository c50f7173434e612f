// What makes a response exceed its limit: the inputs of the runs beyond it,
// mapped to independent standard normal space (u = Phi^-1(F(x)), through
// the normal copula's inverse for correlated inputs: the space subset
// simulation walks in), summarised per input. Reliability methods report
// the same things: the design point (the most likely failing inputs) and
// each input's importance.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "ensemble/response_table.hpp"
#include "job/ensemble_spec.hpp"

namespace treedyn::analysis {

// A bound is "near" within this share of the distribution's range.
inline constexpr double kNearBoundShare = 0.01;
// Failing runs near a bound above this share: P depends on the cut-off.
inline constexpr double kBoundSetsProbability = 0.5;

// Fewer failing runs than this, or than inputs, say little of what makes
// the response fail: by chance alone, every input's divergence is of order
// 1 / runs, and their sum grows with the inputs.
inline constexpr std::uint64_t kFailureRegionRuns = 20;

// The inputs a reader takes as one: a declared [[ensemble.group]] (and
// what a grouped design makes a group: an orientation, a list), else a
// list target's entries (a sea state's phases), else one input.
struct InputUnit {
  std::string name;
  std::vector<unsigned> inputs;
};
std::vector<InputUnit> input_units(const EnsembleSpec& spec);

struct FailureRegion {
  std::uint64_t runs = 0;  // the failing runs it rests on (none: every vector empty)
  // As independent runs: fewer where the runs are states of Markov chains
  // (subset simulation), runs / (1 + gamma) with the chains' correlation
  // factor gamma; `chance` is taken at this many.
  double effective_runs = 0.0;
  // Per input (the columns of /samples/inputs):
  std::vector<double> mean_u;   // mean of u over the failing runs: the design point's estimate
                                // where the region is one-sided
  std::vector<double> mean_u2;  // mean of u^2 (1 for an input the failure does not select on)
  // Relative entropy of the failing runs' u (taken as normal, with their mean
  // m and variance s^2, n - 1) against the input's own N(0, 1),
  // KL = (s^2 + m^2 - 1 - ln s^2) / 2. Sees shifts, two-sided regions
  // (m ~ 0, s > 1) and narrowed spreads alike, where max(mean_u2 - 1, 0)
  // would miss narrowed spreads and add, an input at a time, noise of order
  // 1 / sqrt(runs).
  std::vector<double> divergence;
  double chance = 0.0;  // what KL averages to for an input the failure does not select on
  // max(KL - chance, 0) as a share of its sum over the inputs (NaN when no
  // input departs beyond chance).
  std::vector<double> importance;
  // Share of the failing runs within kNearBoundShare of the range of one of
  // the input's bounds (truncated_normal, uniform; NaN for an unbounded
  // distribution or a full turn of an angle, which is periodic), and that
  // bound (SI), the one most of them are near.
  std::vector<double> near_bound, bound;
  std::vector<double> design_point;  // SI: the inputs at u = mean_u
  // Per input_units(): max(sum of its inputs' KL - their count x chance, 0)
  // as a share of the sum over the units (a unit's chance is taken off once,
  // not per input, where small departures of its many inputs add up).
  std::vector<InputUnit> units;
  std::vector<double> unit_importance;
};

// The failure region of response r (which has a limit) over the rows
// `counted` accepts: the successful ones beyond the limit. `correlation`:
// the runs' chain correlation factor gamma (0: independent runs).
FailureRegion failure_region(const EnsembleSpec& spec, const ensemble::ResponseTable& table, std::size_t r,
                             const std::function<bool(std::uint64_t)>& counted, double correlation = 0.0);

}  // namespace treedyn::analysis
