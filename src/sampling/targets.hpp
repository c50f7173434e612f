// Perturbation targets by name: a parameter of the model (its name, or
// NAME.AXIS for a component of a vector), or a part of a body's initial
// state. Resolved once, when the job is read.
#pragma once

#include <stdexcept>
#include <string>

#include "model/definition.hpp"
#include "sampling/perturbation.hpp"

namespace treedyn::sampling {

struct Target {
  Perturbation::Kind kind = Perturbation::Kind::parameter;
  int first = 0;        // parameter: first entry; state: user body index
  int entries = 1;      // 9 for a whole 3x3 matrix
  double factor = 1.0;  // sampled value -> entry (Perturbation::factor)
  int axis = 0;         // rotation, angular_velocity
  std::string unit;     // SI unit of the sampled values ("kg", "rad", "rad/s", ...)
  std::string enters;   // where it enters, for people
};

// The target's resolution. Throws TargetError saying why a name is not a
// target of this model and what is allowed instead.
class TargetError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
Target resolve_target(const ModelDefinition& model, const std::string& target);
// Resolves p.target and fills p's kind, entries, factor, axis, unit and
// where it enters. Throws TargetError.
void aim(Perturbation& p, const ModelDefinition& model);

}  // namespace treedyn::sampling
