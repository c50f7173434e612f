#include "designs/latin_hypercube/latin_hypercube_points.hpp"

#include <cmath>

#include "sampling/design.hpp"

namespace treedyn::designs {
namespace {

class StrataPoints final : public sampling::PerDimensionPoints {
 public:
  StrataPoints(std::uint64_t seed, std::uint64_t runs, unsigned dimensions)
      : sampling::PerDimensionPoints(dimensions), seed_(seed), runs_(runs) {}
  // Stratum pi_d(k) of N, then a uniform position inside it.
  double uniform(std::uint64_t run, unsigned dimension) const override {
    const std::uint64_t stratum = sampling::permute_index(run, runs_, seed_, dimension);
    const double inside = sampling::counter_uniform(seed_, run, dimension, 1);
    const double n = static_cast<double>(runs_);
    const double u = (static_cast<double>(stratum) + inside) / n;
    // Rounding must not carry u into the next stratum (or to 1).
    const double top = (static_cast<double>(stratum) + 1.0) / n;
    return u < top ? u : std::nextafter(top, 0.0);
  }

 private:
  std::uint64_t seed_;
  std::uint64_t runs_;  // N
};

}  // namespace

std::unique_ptr<sampling::RunPoints> latin_hypercube_points(const sampling::PointsSpec& spec) {
  return std::make_unique<StrataPoints>(spec.seed, spec.runs, spec.dimensions);
}

}  // namespace treedyn::designs
