#include "designs/morris/morris_points.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "sampling/design.hpp"

namespace treedyn::designs {
namespace {

// Streams of counter_uniform and permute_index of this design: apart from
// the other designs' (0, 1) and the bootstraps'.
constexpr std::uint64_t kLowLevelStream = 0x6d6f72726973'01ULL;  // "morris", 1
constexpr std::uint64_t kSideStream = 0x6d6f72726973'02ULL;
constexpr std::uint64_t kOrderStream = 0x6d6f72726973'03ULL;

}  // namespace

MorrisPoints::MorrisPoints(std::uint64_t seed, unsigned levels, std::vector<unsigned> unit_of_dimension, unsigned units)
    : seed_(seed), levels_(levels), unit_of_dimension_(std::move(unit_of_dimension)), units_(units) {
  if (levels_ < 2 || levels_ % 2 != 0) throw std::invalid_argument("morris design: levels must be even, at least 2");
  for (unsigned g : unit_of_dimension_)
    if (g >= units_) throw std::invalid_argument("morris design: a dimension's unit is out of range");
}

std::uint64_t MorrisPoints::position(std::uint64_t trajectory, unsigned unit) const {
  return sampling::permute_index(unit, units_, seed_, kOrderStream + trajectory);
}

bool MorrisPoints::starts_high(std::uint64_t trajectory, unsigned unit) const {
  return sampling::counter_uniform(seed_, trajectory, unit, kSideStream) < 0.5;
}

void MorrisPoints::point(std::uint64_t run, std::span<double> u) const {
  if (u.size() != unit_of_dimension_.size()) throw std::invalid_argument("morris design: one u per input dimension");
  const std::uint64_t t = run / runs_per_trajectory(), s = run % runs_per_trajectory();
  const unsigned half = levels_ / 2;
  for (std::size_t d = 0; d < u.size(); ++d) {
    const unsigned g = unit_of_dimension_[d];
    // floor(v half) < half for v < 1; min() guards against rounding up.
    const double v = sampling::counter_uniform(seed_, t, d, kLowLevelStream);
    const unsigned low = std::min(static_cast<unsigned>(v * half), half - 1);
    const bool high = starts_high(t, g) != (position(t, g) < s);  // moved by run s or before
    u[d] = (static_cast<double>(low + (high ? half : 0u)) + 0.5) / static_cast<double>(levels_);
  }
}

std::vector<MorrisStep> MorrisPoints::steps(std::uint64_t trajectory) const {
  std::vector<MorrisStep> out(units_);
  for (unsigned g = 0; g < units_; ++g) out[position(trajectory, g)] = {g, starts_high(trajectory, g) ? -1.0 : 1.0};
  return out;
}

}  // namespace treedyn::designs
