#include "designs/saltelli/saltelli_points.hpp"

#include "sampling/design.hpp"

namespace treedyn::designs {
namespace {

class SaltelliPoints final : public ensemble::TwoPointRuns {
 public:
  using TwoPointRuns::TwoPointRuns;

 private:
  ensemble::SaltelliPlace place(std::uint64_t run) const override { return ensemble::saltelli_place(run, units()); }
};

}  // namespace

std::unique_ptr<ensemble::RunPoints> saltelli_points(const ensemble::PointsSpec& spec) {
  ensemble::check_sobol_size(ensemble::name(ensemble::Design::saltelli), 2 * spec.dimensions,
                             spec.runs / ensemble::saltelli_block(spec.units));
  return std::make_unique<SaltelliPoints>(spec);
}

}  // namespace treedyn::designs
