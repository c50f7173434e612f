#include "designs/monte_carlo/monte_carlo_points.hpp"

#include "sampling/design.hpp"

namespace treedyn::designs {
namespace {

class CounterPoints final : public sampling::PerDimensionPoints {
 public:
  CounterPoints(std::uint64_t seed, unsigned dimensions) : sampling::PerDimensionPoints(dimensions), seed_(seed) {}
  double uniform(std::uint64_t run, unsigned dimension) const override {
    return sampling::counter_uniform(seed_, run, dimension, 0);
  }

 private:
  std::uint64_t seed_;
};

}  // namespace

std::unique_ptr<sampling::RunPoints> monte_carlo_points(const sampling::PointsSpec& spec) {
  return std::make_unique<CounterPoints>(spec.seed, spec.dimensions);
}

}  // namespace treedyn::designs
