#include "ensemble/perturbation.hpp"

#include <stdexcept>

namespace treedyn::ensemble {
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

Harmonic& harmonic_term(ModelSpec& spec, int axis, int term) {
  auto* h = std::get_if<HarmonicBase>(&spec.base_motion);
  if (!h || term >= static_cast<int>(h->axes[axis].size()))
    throw std::logic_error("perturbation of a harmonic term the base does not have");
  return h->axes[axis][term];
}

}  // namespace

std::vector<std::string> Perturbation::input_names() const {
  if (field == Field::orientation) return {target + ".x", target + ".y", target + ".z"};
  return {target};
}

void Perturbation::sample(std::span<const double> u, std::span<double> values) const {
  for (std::size_t d = 0; d < u.size(); ++d) values[d] = distribution.quantile(u[d]) * unit;
}

void Perturbation::apply(std::span<const double> v, ModelSpec& spec, TreeState& state) const {
  const double x = v[0];
  switch (field) {
    case Field::mass: {
      double& m = spec.bodies[body_index].mass;
      m = combine(mode, m, x);
      return;
    }
    case Field::inertia_scale:
      spec.bodies[body_index].inertia *= x;
      return;
    case Field::joint_on_child: {
      double& c = spec.joints[joint_index].on_child[axis];
      c = combine(mode, c, x);
      return;
    }
    case Field::joint_on_parent: {
      double& c = spec.joints[joint_index].on_parent[axis];
      c = combine(mode, c, x);
      return;
    }
    case Field::orientation: {
      const Vec3 rotation_vector(v[0], v[1], v[2]);
      const double angle = rotation_vector.norm();
      if (angle > 0.0)
        state.rotation[body_index] =
            Eigen::AngleAxisd(angle, rotation_vector / angle).toRotationMatrix() *
            state.rotation[body_index];
      return;
    }
    case Field::rotation:
      state.rotation[body_index] =
          Eigen::AngleAxisd(x, Vec3::Unit(axis)).toRotationMatrix() * state.rotation[body_index];
      return;
    case Field::angular_velocity: {
      double& w = state.angular_velocity[body_index][axis];
      w = combine(mode, w, x);
      return;
    }
    case Field::stiffness:
    case Field::damping: {
      Mat3& m = field == Field::stiffness ? spec.joints[joint_index].spring.stiffness
                                          : spec.joints[joint_index].spring.damping;
      if (mode == Mode::scale)
        m *= x;
      else if (mode == Mode::add)
        m += x * Mat3::Identity();
      else
        m = x * Mat3::Identity();
      return;
    }
    case Field::base_amplitude: {
      double& a = harmonic_term(spec, axis, term).amplitude;
      a = combine(mode, a, x);
      return;
    }
    case Field::base_frequency: {
      double& f = harmonic_term(spec, axis, term).frequency;
      f = combine(mode, f, x);
      return;
    }
    case Field::base_phase: {
      double& p = harmonic_term(spec, axis, term).phase;
      p = combine(mode, p, x);
      return;
    }
    case Field::base_acceleration: {
      auto* c = std::get_if<ConstantAccelerationBase>(&spec.base_motion);
      if (!c) throw std::logic_error("perturbation of base acceleration without such a base");
      c->acceleration[axis] = combine(mode, c->acceleration[axis], x);
      return;
    }
    case Field::gravity:
      spec.gravity[axis] = combine(mode, spec.gravity[axis], x);
      return;
  }
}

}  // namespace treedyn::ensemble
