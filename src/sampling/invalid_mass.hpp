// How often a perturbation draws a value the model refuses: the probability
// mass of its distribution outside the parameter's valid range (a mass
// <= 0, a negative frequency, a spring that is not positive semi-definite),
// from the distribution's CDF. `treedyn-ensemble --check` prints it and
// warns above 0.1 %: each such sample fails as an invalid model (status 2).
#pragma once

#include <optional>
#include <string>

#include "model/definition.hpp"
#include "sampling/perturbation.hpp"

namespace treedyn::sampling {

struct InvalidMass {
  double probability = 0.0;  // of a sample being refused
  std::string valid;         // what the model accepts, e.g. "body.rod.mass > 0 kg"
};

// nullopt for targets the model accepts any value of (initial state,
// positions, gravity, ...).
std::optional<InvalidMass> invalid_mass(const Perturbation& p, const ModelDefinition& d);

inline constexpr double kInvalidMassWarning = 1e-3;

}  // namespace treedyn::sampling
