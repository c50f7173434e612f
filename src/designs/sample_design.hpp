// A design's points, as the ensemble holds them: made by the design's
// DesignRules::points (designs/<name>/), from the seed, the run count, the
// input dimensions and their units.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "sampling/design.hpp"
#include "sampling/run_points.hpp"

namespace treedyn::designs {

class SampleDesign {
 public:
  // `unit_of_dimension` (saltelli, morris): the unit of each input
  // dimension, 0 .. U-1; empty: every dimension is a unit of its own
  // (U = D). `morris`: its variant and levels.
  SampleDesign(sampling::Design design, std::uint64_t seed, std::uint64_t runs, unsigned dimensions,
               std::vector<unsigned> unit_of_dimension = {}, const std::optional<MorrisSpec>& morris = {});

  // u in the open interval (0, 1).
  double uniform(std::uint64_t run, unsigned dimension) const { return points_->uniform(run, dimension); }
  // All dimensions of one run at once (u.size() == dimensions()).
  void point(std::uint64_t run, std::span<double> u) const { points_->point(run, u); }

 private:
  std::unique_ptr<const sampling::RunPoints> points_;
};

}  // namespace treedyn::designs
