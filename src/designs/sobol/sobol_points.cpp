#include "designs/sobol/sobol_points.hpp"

#include "sampling/design.hpp"

namespace treedyn::designs {
namespace {

class SobolPoints final : public ensemble::RunPoints {
 public:
  SobolPoints(std::uint64_t seed, unsigned dimensions) : ensemble::RunPoints(dimensions), seed_(seed) {}
  void point(std::uint64_t run, std::span<double> u) const override {
    ensemble::scrambled_sobol_point(seed_, run, dimensions(), 0, u);
  }
  double uniform(std::uint64_t run, unsigned dimension) const override {
    return ensemble::scrambled_sobol_uniform(seed_, run, dimension, dimensions());
  }

 private:
  std::uint64_t seed_;
};

}  // namespace

std::unique_ptr<ensemble::RunPoints> sobol_points(const ensemble::PointsSpec& spec) {
  ensemble::check_sobol_size(ensemble::name(ensemble::Design::sobol), spec.dimensions, spec.runs);
  return std::make_unique<SobolPoints>(spec.seed, spec.dimensions);
}

}  // namespace treedyn::designs
