#include "designs/morris/morris_run_points.hpp"

#include "designs/morris/morris_points.hpp"
#include "sampling/design.hpp"

namespace treedyn::designs {
namespace {

// Run s of trajectory t: A_t (s = 0), then A_t with unit s - 1 from B_t.
class RadialPoints final : public sampling::TwoPointRuns {
 public:
  using TwoPointRuns::TwoPointRuns;

 private:
  sampling::SaltelliPlace place(std::uint64_t run) const override {
    const std::uint64_t t = run / (units() + 1u), s = run % (units() + 1u);
    return {t, s == 0 ? sampling::SaltelliRole::a : sampling::SaltelliRole::ab,
            s == 0 ? 0u : static_cast<unsigned>(s - 1)};
  }
};

class TrajectoryPoints final : public sampling::RunPoints {
 public:
  explicit TrajectoryPoints(const sampling::PointsSpec& spec)
      : sampling::RunPoints(spec.dimensions),
        points_(spec.seed, spec.morris->levels, spec.unit_of_dimension, spec.units) {}
  void point(std::uint64_t run, std::span<double> u) const override { points_.point(run, u); }

 private:
  MorrisPoints points_;
};

}  // namespace

std::unique_ptr<sampling::RunPoints> morris_run_points(const sampling::PointsSpec& spec) {
  if (spec.morris && !spec.morris->radial) return std::make_unique<TrajectoryPoints>(spec);
  sampling::check_sobol_size(name(sampling::Design::morris), 2 * spec.dimensions, spec.runs / (spec.units + 1u));
  return std::make_unique<RadialPoints>(spec);
}

}  // namespace treedyn::designs
