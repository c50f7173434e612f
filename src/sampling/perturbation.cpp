#include "sampling/perturbation.hpp"

namespace treedyn::sampling {
namespace {

double combine(Perturbation::Mode mode, double nominal, double value) {
  switch (mode) {
    case Perturbation::Mode::set:
      return value;
    case Perturbation::Mode::add:
      return nominal + value;
    case Perturbation::Mode::scale:
      return nominal * value;
  }
  return value;
}

}  // namespace

std::vector<std::string> Perturbation::input_names() const {
  if (kind == Kind::orientation) return {target + ".x", target + ".y", target + ".z"};
  if (kind == Kind::parameter_list) {
    std::vector<std::string> names;
    for (int k = 1; k <= entries; ++k) names.push_back(target + "[" + std::to_string(k) + "]");
    return names;
  }
  return {target};
}

void Perturbation::sample(std::span<const double> u, std::span<double> values) const {
  for (std::size_t d = 0; d < u.size(); ++d) values[d] = distribution.quantile(u[d]) * unit;
}

void Perturbation::apply(std::span<const double> v, std::span<double> parameters, InitialState& state) const {
  const double x = v[0];
  switch (kind) {
    case Kind::parameter:
      if (entries == 1) {
        parameters[first] = mode == Mode::scale ? parameters[first] * x : combine(mode, parameters[first], x * factor);
      } else {
        // A 3x3 matrix, row-major: set and add use x E, scale the whole matrix.
        for (int k = 0; k < entries; ++k) {
          double& entry = parameters[first + k];
          const double identity = k % 4 == 0 ? 1.0 : 0.0;
          entry = mode == Mode::scale ? entry * x : mode == Mode::add ? entry + x * identity : x * identity;
        }
      }
      return;
    case Kind::orientation: {
      const Vec3 rotation_vector(v[0], v[1], v[2]);
      const double angle = rotation_vector.norm();
      if (angle > 0.0)
        state.rotation[first] =
            Eigen::AngleAxisd(angle, rotation_vector / angle).toRotationMatrix() * state.rotation[first];
      return;
    }
    case Kind::parameter_list:
      for (int k = 0; k < entries; ++k)
        parameters[first + k] = combine(mode, parameters[first + k], v[static_cast<std::size_t>(k)] * factor);
      return;
    case Kind::rotation:
      state.rotation[first] = Eigen::AngleAxisd(x, Vec3::Unit(axis)).toRotationMatrix() * state.rotation[first];
      return;
    case Kind::angular_velocity: {
      double& w = state.angular_velocity[first][axis];
      w = combine(mode, w, x);
      return;
    }
  }
}

void apply_inputs(std::span<const Perturbation> perturbations, std::span<const double> inputs,
                  const InitialState& nominal_state, std::span<double> parameters, InitialState& state) {
  auto apply = [&](bool angular_velocity) {
    std::size_t d = 0;
    for (const Perturbation& p : perturbations) {
      const auto n = static_cast<std::size_t>(p.dimensions());
      if ((p.kind == Perturbation::Kind::angular_velocity) == angular_velocity)
        p.apply(inputs.subspan(d, n), parameters, state);
      d += n;
    }
  };
  apply(false);
  // A spin the job gave in a body's own frame turns with the body; the
  // angular-velocity perturbations, in inertial components, come after.
  turn_body_frame_spins(nominal_state, state);
  apply(true);
}

}  // namespace treedyn::sampling
