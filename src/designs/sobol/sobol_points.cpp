#include "designs/sobol/sobol_points.hpp"

#include "sampling/design.hpp"

namespace treedyn::designs {
namespace {

class SobolPoints final : public sampling::RunPoints {
 public:
  SobolPoints(std::uint64_t seed, unsigned dimensions) : sampling::RunPoints(dimensions), seed_(seed) {}
  void point(std::uint64_t run, std::span<double> u) const override {
    sampling::scrambled_sobol_point(seed_, run, dimensions(), 0, u);
  }
  double uniform(std::uint64_t run, unsigned dimension) const override {
    return sampling::scrambled_sobol_uniform(seed_, run, dimension, dimensions());
  }

 private:
  std::uint64_t seed_;
};

}  // namespace

std::unique_ptr<sampling::RunPoints> sobol_points(const sampling::PointsSpec& spec) {
  sampling::check_sobol_size(name(sampling::Design::sobol), spec.dimensions, spec.runs);
  return std::make_unique<SobolPoints>(spec.seed, spec.dimensions);
}

}  // namespace treedyn::designs
