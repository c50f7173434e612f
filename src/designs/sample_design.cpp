#include "designs/sample_design.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "designs/design_rules.hpp"

namespace treedyn::designs {

SampleDesign::SampleDesign(sampling::Design design, std::uint64_t seed, std::uint64_t runs, unsigned dimensions,
                           std::vector<unsigned> unit_of_dimension, const std::optional<MorrisSpec>& morris) {
  sampling::PointsSpec spec{seed, runs, dimensions, std::move(unit_of_dimension), dimensions, morris};
  if (spec.unit_of_dimension.empty())
    for (unsigned d = 0; d < dimensions; ++d) spec.unit_of_dimension.push_back(d);
  if (spec.unit_of_dimension.size() != dimensions)
    throw std::invalid_argument("sample design: one Saltelli unit per input dimension");
  spec.units =
      dimensions == 0 ? 0 : *std::max_element(spec.unit_of_dimension.begin(), spec.unit_of_dimension.end()) + 1;
  points_ = rules_of(design).points(spec);
}

}  // namespace treedyn::designs
