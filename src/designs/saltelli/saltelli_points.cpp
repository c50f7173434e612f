#include "designs/saltelli/saltelli_points.hpp"

#include "sampling/design.hpp"

namespace treedyn::designs {
namespace {

class SaltelliPoints final : public sampling::TwoPointRuns {
 public:
  using TwoPointRuns::TwoPointRuns;

 private:
  sampling::SaltelliPlace place(std::uint64_t run) const override { return sampling::saltelli_place(run, units()); }
};

}  // namespace

std::unique_ptr<sampling::RunPoints> saltelli_points(const sampling::PointsSpec& spec) {
  sampling::check_sobol_size(name(sampling::Design::saltelli), 2 * spec.dimensions,
                             spec.runs / sampling::saltelli_block(spec.units));
  return std::make_unique<SaltelliPoints>(spec);
}

}  // namespace treedyn::designs
