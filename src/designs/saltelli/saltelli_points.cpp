#include "designs/saltelli/saltelli_points.hpp"

#include "sampling/design.hpp"

namespace treedyn::ensemble {
namespace {

class SaltelliPoints final : public RunPoints {
 public:
  explicit SaltelliPoints(const PointsSpec& spec)
      : RunPoints(spec.dimensions), seed_(spec.seed), unit_of_dimension_(spec.unit_of_dimension), units_(spec.units) {}
  void point(std::uint64_t run, std::span<double> u) const override {
    saltelli_point(seed_, unit_of_dimension_, saltelli_place(run, units_), u);
  }

 private:
  std::uint64_t seed_;
  std::vector<unsigned> unit_of_dimension_;
  unsigned units_;  // U
};

}  // namespace

std::unique_ptr<RunPoints> saltelli_points(const PointsSpec& spec) {
  check_sobol_size("saltelli", 2 * spec.dimensions, spec.runs / saltelli_block(spec.units));
  return std::make_unique<SaltelliPoints>(spec);
}

}  // namespace treedyn::ensemble
