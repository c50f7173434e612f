// [ensemble.morris] of design = "morris": the screen's size, its steps and grid.
#pragma once

#include <cstdint>

namespace treedyn::designs {

struct MorrisSpec {
  std::uint64_t trajectories = 0;  // r: runs are r (U + 1)
  // Radial (Campolongo, Saltelli and Cariboni 2011): each step takes one
  // factor's inputs from an independent point b, scrambled Sobol' over 2D
  // dimensions as Saltelli's A and B; else Morris' trajectories on p levels.
  bool radial = true;
  unsigned levels = 4;  // p, even (trajectories only): the levels (l + 1/2) / p of every input's u
};

}  // namespace treedyn::designs
