// One perturbed input of an ensemble: which field of the job it changes, how,
// and with what distribution.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "ensemble/distribution.hpp"
#include "integrate/tree_ode.hpp"
#include "model/model_spec.hpp"

namespace treedyn::ensemble {

struct Perturbation {
  enum class Field {
    mass,              // body.NAME.mass
    inertia_scale,     // body.NAME.inertia_scale: multiplies the inertia tensor
    joint_on_child,    // body.NAME.joint_on_child.AXIS
    joint_on_parent,   // body.NAME.joint_on_parent.AXIS
    orientation,       // body.NAME.orientation: small rotation vector (3 inputs)
    rotation,          // body.NAME.rotation.AXIS: extra rotation about an inertial axis
    angular_velocity,  // body.NAME.angular_velocity.AXIS: inertial component
    stiffness,         // joint.CHILD.stiffness (isotropic value, or scale of the matrix)
    damping,           // joint.CHILD.damping
    base_amplitude,    // base.AXIS[K].amplitude
    base_frequency,    // base.AXIS[K].frequency
    base_phase,        // base.AXIS[K].phase
    base_acceleration, // base.acceleration.AXIS (constant_acceleration base)
    gravity,           // gravity.AXIS
  };
  enum class Mode { set, add, scale };

  std::string target;     // as written in the job file
  Field field = Field::mass;
  std::string body;       // user body name (or joint child)
  int body_index = -1;    // in ModelSpec::bodies
  int joint_index = -1;   // in ModelSpec::joints
  int axis = 0;           // 0, 1, 2 = x, y, z
  int term = 0;           // harmonic term, 0-based
  Mode mode = Mode::set;
  double unit = 1.0;      // multiplies sampled values into SI (deg -> rad, ...)
  Distribution distribution;

  int dimensions() const { return field == Field::orientation ? 3 : 1; }
  // Column names of the sampled inputs, e.g. "body.rod.orientation.x".
  std::vector<std::string> input_names() const;
  // Physical input values (SI) from uniforms (one per dimension).
  void sample(std::span<const double> u, std::span<double> values) const;
  // Changes the model description and the initial state.
  void apply(std::span<const double> values, ModelSpec& spec, TreeState& state) const;
};

}  // namespace treedyn::ensemble
