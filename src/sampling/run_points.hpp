// The inputs of a design's runs in the unit cube: run k's u in (0, 1)^D is a
// pure function of (seed, k), so run k is the same whichever rank computes
// it and in whatever order. Each design makes its own (src/designs/<name>/,
// through its DesignRules::points); SampleDesign (designs/sample_design.hpp)
// is what the rest of the ensemble holds. (Subset simulation's chains,
// after its level 0, draw their own: designs/subset_simulation/subset_simulation.hpp.)
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "designs/morris/morris_spec.hpp"
#include "sampling/design.hpp"

namespace treedyn::sampling {

// What a design's points are made from.
struct PointsSpec {
  std::uint64_t seed = 0;
  std::uint64_t runs = 0;                     // N
  unsigned dimensions = 0;                    // D
  std::vector<unsigned> unit_of_dimension;    // size D: the unit 0 .. U-1 of each dimension
  unsigned units = 0;                         // U
  std::optional<designs::MorrisSpec> morris;  // design = "morris": its variant and levels
};

class RunPoints {
 public:
  explicit RunPoints(unsigned dimensions) : dimensions_(dimensions) {}
  virtual ~RunPoints() = default;

  // Run `run`'s u, every dimension (u.size() == dimensions()).
  virtual void point(std::uint64_t run, std::span<double> u) const = 0;
  // One dimension alone; from the whole point unless a design can do better.
  virtual double uniform(std::uint64_t run, unsigned dimension) const {
    std::vector<double> all(dimensions_);
    point(run, all);
    return all[dimension];
  }
  unsigned dimensions() const { return dimensions_; }

 private:
  unsigned dimensions_;
};

// A design whose dimensions are drawn one at a time (monte_carlo,
// latin_hypercube): the point is its uniforms.
class PerDimensionPoints : public RunPoints {
 public:
  using RunPoints::RunPoints;
  double uniform(std::uint64_t run, unsigned dimension) const override = 0;
  void point(std::uint64_t run, std::span<double> u) const final {
    for (unsigned d = 0; d < u.size(); ++d) u[d] = uniform(run, d);
  }
};

// A design whose runs are Saltelli's A, B and AB points (saltelli_point):
// saltelli, and morris' radial steps; each says which run is which.
class TwoPointRuns : public RunPoints {
 public:
  explicit TwoPointRuns(const PointsSpec& spec)
      : RunPoints(spec.dimensions), seed_(spec.seed), unit_of_dimension_(spec.unit_of_dimension), units_(spec.units) {}
  void point(std::uint64_t run, std::span<double> u) const final {
    saltelli_point(seed_, unit_of_dimension_, place(run), u);
  }

 protected:
  unsigned units() const { return units_; }  // U
  virtual SaltelliPlace place(std::uint64_t run) const = 0;

 private:
  std::uint64_t seed_;
  std::vector<unsigned> unit_of_dimension_;
  unsigned units_;
};

}  // namespace treedyn::sampling
