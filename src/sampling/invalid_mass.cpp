#include "sampling/invalid_mass.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>

namespace treedyn::sampling {
namespace {

using Mode = Perturbation::Mode;

// The values of the distribution's variable that the model accepts, as one
// bound: d > bound (above) or d < bound (below); `always`/`never` when the
// answer does not depend on d.
struct Bound {
  enum class Kind { above, below, always, never } kind = Kind::always;
  double bound = 0.0;
};

// value = slope x + offset must stay in `range` (x: the SI input).
Bound linear(const ValidRange& range, double slope, double offset, double unit) {
  if (slope == 0.0) {
    const bool valid = range.low_open ? offset > range.low : offset >= range.low;
    return {valid ? Bound::Kind::always : Bound::Kind::never};
  }
  const double x = (range.low - offset) / slope;
  return {slope > 0.0 ? Bound::Kind::above : Bound::Kind::below, x / unit};
}

// The smallest eigenvalue of a (symmetrised) 3x3 matrix from the vector.
double smallest_eigenvalue(std::span<const double> entries) {
  Mat3 m;
  for (int k = 0; k < 9; ++k) m(k / 3, k % 3) = entries[k];
  return Eigen::SelfAdjointEigenSolver<Mat3>(0.5 * (m + m.transpose()), Eigen::EigenvaluesOnly).eigenvalues()[0];
}

Bound bound_of(const Perturbation& p, const ValidRange& range, std::span<const double> nominal) {
  if (p.entries == 1) {
    const double v0 = nominal[p.first];
    if (p.mode == Mode::scale) return linear(range, v0, 0.0, p.unit);
    return linear(range, p.factor, p.mode == Mode::add ? v0 : 0.0, p.unit);
  }
  // A matrix: set gives x E, add adds x E, scale multiplies; its smallest
  // eigenvalue must stay in range (for scale: every eigenvalue times x).
  const double lowest = smallest_eigenvalue(nominal.subspan(static_cast<std::size_t>(p.first), 9));
  if (p.mode == Mode::set) return linear(range, 1.0, 0.0, p.unit);
  if (p.mode == Mode::add) return linear(range, 1.0, lowest, p.unit);
  return linear(range, lowest, 0.0, p.unit);
}

}  // namespace

std::optional<InvalidMass> invalid_mass(const Perturbation& p, const ModelDefinition& d) {
  if (p.kind != Perturbation::Kind::parameter) return std::nullopt;
  const Parameter& parameter = d.parameters.owner(p.first);
  if (!parameter.valid.bounded()) return std::nullopt;
  const Bound b = bound_of(p, parameter.valid, d.parameters.nominal());
  InvalidMass m;
  m.valid = d.parameters.entry_name(p.first) + " " + parameter.valid.describe(parameter.unit);
  if (p.entries > 1) m.valid = parameter.name + ": every eigenvalue " + parameter.valid.describe(parameter.unit);
  if ((b.kind == Bound::Kind::above || b.kind == Bound::Kind::below) && !std::isfinite(b.bound)) {
    const bool none_valid = (b.kind == Bound::Kind::above) == (b.bound > 0.0);
    m.probability = none_valid ? 1.0 : 0.0;
    return m;
  }
  switch (b.kind) {
    case Bound::Kind::always:
      m.probability = 0.0;
      break;
    case Bound::Kind::never:
      m.probability = 1.0;
      break;
    case Bound::Kind::above:
      m.probability = p.distribution.cdf(b.bound);
      break;
    case Bound::Kind::below:
      m.probability = 1.0 - p.distribution.cdf(b.bound);
      break;
  }
  return m;
}

}  // namespace treedyn::sampling
