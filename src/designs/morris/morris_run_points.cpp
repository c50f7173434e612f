#include "designs/morris/morris_run_points.hpp"

#include "designs/morris/morris_points.hpp"
#include "sampling/design.hpp"

namespace treedyn::ensemble {
namespace {

class RadialPoints final : public RunPoints {
 public:
  explicit RadialPoints(const PointsSpec& spec)
      : RunPoints(spec.dimensions), seed_(spec.seed), unit_of_dimension_(spec.unit_of_dimension), units_(spec.units) {}
  void point(std::uint64_t run, std::span<double> u) const override {
    const std::uint64_t t = run / (units_ + 1u), s = run % (units_ + 1u);
    saltelli_point(seed_, unit_of_dimension_,
                   {t, s == 0 ? SaltelliRole::a : SaltelliRole::ab, s == 0 ? 0u : static_cast<unsigned>(s - 1)}, u);
  }

 private:
  std::uint64_t seed_;
  std::vector<unsigned> unit_of_dimension_;
  unsigned units_;  // U
};

class TrajectoryPoints final : public RunPoints {
 public:
  explicit TrajectoryPoints(const PointsSpec& spec)
      : RunPoints(spec.dimensions), points_(spec.seed, spec.morris->levels, spec.unit_of_dimension, spec.units) {}
  void point(std::uint64_t run, std::span<double> u) const override { points_.point(run, u); }

 private:
  MorrisPoints points_;
};

}  // namespace

std::unique_ptr<RunPoints> morris_run_points(const PointsSpec& spec) {
  if (spec.morris && !spec.morris->radial) return std::make_unique<TrajectoryPoints>(spec);
  check_sobol_size("morris", 2 * spec.dimensions, spec.runs / (spec.units + 1u));
  return std::make_unique<RadialPoints>(spec);
}

}  // namespace treedyn::ensemble
