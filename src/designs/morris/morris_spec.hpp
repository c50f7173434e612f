// [ensemble.morris] of design = "morris": the screen's size and grid.
#pragma once

#include <cstdint>

namespace treedyn::ensemble {

struct MorrisSpec {
  std::uint64_t trajectories = 0;  // r: runs are r (U + 1)
  unsigned levels = 4;             // p, even: the levels (l + 1/2) / p of every input's u
};

}  // namespace treedyn::ensemble
