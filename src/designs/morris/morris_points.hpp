// Morris' elementary-effects design (Morris 1991), with groups as in
// Campolongo, Cariboni and Saltelli 2007: r trajectories of U + 1 runs
// each over U units (an input, or a group of inputs moved together). Run
// s of a trajectory differs from run s - 1 in exactly one unit, whose
// inputs all step by Delta the same way; after U steps every unit has
// moved once.
//
// The levels are the centres of p equal-probability bins, u = (l + 1/2) / p
// for l = 0 .. p - 1 (p even), not Morris' grid 0, 1/(p-1), .., 1: a grid
// point at u = 0 or 1 is an infinite input for a normal distribution, and
// the centres cover each bin of probability alike. A step moves an input
// p/2 levels, Delta = 1/2 in u: each input takes one of its two values
// l and l + p/2 (l uniform in 0 .. p/2 - 1, drawn per input), so every run
// is an input grid point drawn uniformly.
//
// Every run's inputs are a pure function of (seed, run index): run k is run
// s = k mod (U + 1) of trajectory t = k / (U + 1); the trajectory's unit
// order is a keyed permutation of the units (permute_index), each input's
// low level and each unit's starting side are counter-based draws keyed by
// (seed, t). So any rank, a resume or `--sample K` makes the same run.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace treedyn::designs {

// Delta in u: every step moves an input by half the unit interval.
inline constexpr double kMorrisDelta = 0.5;

struct MorrisStep {
  unsigned unit = 0;       // the unit step s moved
  double direction = 1.0;  // +1: its inputs went up by Delta; -1: down
};

class MorrisPoints {
 public:
  // `unit_of_dimension`: the unit 0 .. U-1 of each input dimension.
  MorrisPoints(std::uint64_t seed, unsigned levels, std::vector<unsigned> unit_of_dimension, unsigned units);

  std::uint64_t runs_per_trajectory() const { return units_ + 1u; }
  // Run `run`'s u in (0, 1), one per input dimension.
  void point(std::uint64_t run, std::span<double> u) const;
  // Steps 1 .. U of trajectory t (element s - 1: what run s moved).
  std::vector<MorrisStep> steps(std::uint64_t trajectory) const;

 private:
  // The position 0 .. U-1 at which trajectory t moves `unit`.
  std::uint64_t position(std::uint64_t trajectory, unsigned unit) const;
  bool starts_high(std::uint64_t trajectory, unsigned unit) const;

  std::uint64_t seed_;
  unsigned levels_;
  std::vector<unsigned> unit_of_dimension_;
  unsigned units_;
};

}  // namespace treedyn::designs
