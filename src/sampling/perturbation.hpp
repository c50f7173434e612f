// One perturbed input of an ensemble: which parameter entries or which part
// of the initial state it changes, how, and with what distribution. Targets
// are resolved to vector indices when the job is read (read_ensemble.cpp);
// applying one is a few arithmetic operations, no names.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "common/enum_names.hpp"
#include "model/initial_state.hpp"
#include "sampling/distribution.hpp"

namespace treedyn::sampling {

struct Perturbation {
  enum class Kind {
    parameter,         // entries of the parameter vector (model/parameters.hpp)
    orientation,       // body.NAME.orientation: a small rotation vector (3 inputs), inertial axes
    rotation,          // body.NAME.rotation.AXIS: an extra rotation about an inertial axis
    angular_velocity,  // body.NAME.angular_velocity.AXIS: an inertial component
    parameter_list,    // every entry of a list parameter (base.AXIS.phases), one input each
  };
  enum class Mode { set, add, scale };

  std::string target;  // as written in the job file
  Kind kind = Kind::parameter;
  int first = 0;        // parameter: its first entry; otherwise the user index of the body
  int entries = 1;      // parameter entries changed: 1, or 9 for a whole 3x3 matrix
                        // (set / add: an isotropic value k E; scale: the whole matrix);
                        // parameter_list: the list's length, one input per entry
  double factor = 1.0;  // parameter, set / add: the entry changes by x * factor (a mass
                        // target on a solid given by its density: 1 / nominal volume)
  int axis = 0;         // rotation, angular_velocity: 0, 1, 2 = x, y, z
  Mode mode = Mode::set;
  double unit = 1.0;  // multiplies sampled values into SI (deg -> rad, ...)
  Distribution distribution;
  std::string si_unit;  // of the values after `unit`, e.g. "kg", "rad"
  std::string enters;   // where it enters the model, for people

  int dimensions() const { return kind == Kind::orientation ? 3 : kind == Kind::parameter_list ? entries : 1; }
  // Column names of the sampled inputs, e.g. "body.rod.orientation.x".
  std::vector<std::string> input_names() const;
  // Physical input values (SI) from uniforms (one per dimension).
  void sample(std::span<const double> u, std::span<double> values) const;
  // Changes the parameter vector or the initial state by the sampled values.
  void apply(std::span<const double> values, std::span<double> parameters, InitialState& state) const;
};

inline constexpr NameTable<Perturbation::Mode, 3> kModeNames{
    {{Perturbation::Mode::set, "set"}, {Perturbation::Mode::add, "add"}, {Perturbation::Mode::scale, "scale"}}};

// Applies a sample's inputs (values of `perturbations`, concatenated) to the
// nominal parameter vector and initial state, in the one order every run
// uses: parameters and orientations first, then the job's body-frame spins
// turned with their bodies, then the angular-velocity perturbations (inertial).
void apply_inputs(std::span<const Perturbation> perturbations, std::span<const double> inputs,
                  const InitialState& nominal_state, std::span<double> parameters, InitialState& state);

}  // namespace treedyn::sampling
