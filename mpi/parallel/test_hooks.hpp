// The seam through which the tests of kills and signals drive a run into a
// known state (hidden options of treedyn-ensemble; never set by users).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>

namespace treedyn::parallel {

struct TestHooks {
  // --test-hold-after N: every rank holds after keeping N samples of the
  // waves after the pilot: it saves its checkpoint (unless hold_unsaved:
  // then only a stop signal's save puts them on disk), writes
  // OUT.h5.checkpoint/held-rankR ("pid P kept K": its process and every
  // sample it has kept) and waits for a stop signal (or SIGKILL).
  std::optional<std::uint64_t> hold_after;
  bool hold_unsaved = false;  // --test-hold-unsaved
  // --test-unit-rows R: units of R rows (ensemble/capacity.hpp: unit_rows)
  // whatever the samples and ranks, 0 none; for the tests and benchmarks of
  // units on small runs.
  std::optional<std::size_t> unit_rows;
};

}  // namespace treedyn::parallel
