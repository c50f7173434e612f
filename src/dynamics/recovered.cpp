#include "dynamics/recovered.hpp"

#include <cmath>

namespace treedyn {

Recovered recover(const Model& model, const Data& data) {
  Recovered out;
  recover(model, data, out);
  return out;
}

namespace {

// Top-down in the regular order (parents first), stored at the user's
// index: each CoM from its inboard joint point (20); with accelerations,
// X_a = sum over sub(a) of m_i r_i'' - F_i (12), bottom-up.
void recover_points(const Model& model, const Data& data, Recovered& out, bool accelerations) {
  for (int i = 0; i < model.n; ++i) {
    const int u = model.tree().user_index[i];
    const int p = model.tree().parent[i];
    const Vec3& w = data.angular_velocity[i];
    Vec3 jp = data.base.position, jv = data.base.velocity, ja = data.base.acceleration;
    if (p != kBase) {
      const int up = model.tree().user_index[p];
      const Vec3 arm = data.rotation[p] * model.parent_com_to_joint[i];
      const Vec3& wp = data.angular_velocity[p];
      jp = out.com_position[up] + arm;
      jv = out.com_velocity[up] + wp.cross(arm);
      if (accelerations)
        ja = out.com_acceleration[up] + out.angular_acceleration[up].cross(arm) + wp.cross(wp.cross(arm));
    }
    const Vec3& c = data.com_to_inboard_joint[i];
    out.rotation[u] = data.rotation[i];
    out.angular_velocity[u] = w;
    out.joint_position[u] = jp;
    out.com_position[u] = jp - c;
    out.com_velocity[u] = jv - w.cross(c);
    out.joint_moment[u] = data.joint_moment[i];
    if (!accelerations) continue;
    const Vec3 wdot = data.angular_acceleration.segment<3>(3 * i);
    out.angular_acceleration[u] = wdot;
    out.com_acceleration[u] = ja - wdot.cross(c) - w.cross(w.cross(c));
    out.joint_reaction[u] = model.mass[i] * out.com_acceleration[u] - data.force[i];
  }
  if (!accelerations) return;
  for (int i = model.n - 1; i >= 1; --i)
    out.joint_reaction[model.tree().user_index[model.tree().parent[i]]] +=
        out.joint_reaction[model.tree().user_index[i]];
}

// Joint angles and axes, energies and the angular momentum, as `parts` asks.
void recover_totals(const Model& model, const Data& data, Recovered& out, unsigned parts) {
  for (int i = 0; i < model.n; ++i) {
    const int u = model.tree().user_index[i];
    const Mat3& A = data.rotation[i];
    const Vec3& w = data.angular_velocity[i];
    if (parts & kRecoverJointAngles) {
      const int p = model.tree().parent[i];
      const Mat3 relative = p == kBase ? A : Mat3(data.rotation[p].transpose() * A);
      const Eigen::AngleAxisd aa(relative);
      out.joint_angle[u] = aa.angle();
      out.joint_axis[u] = aa.angle() > 0.0 ? Vec3(aa.axis()) : Vec3::Zero();
    }
    if (!(parts & (kRecoverEnergy | kRecoverAngularMomentum))) continue;
    const Vec3& r = out.com_position[u];
    const Vec3& v = out.com_velocity[u];
    const Mat3 inertia = A * model.inertia[i] * A.transpose();
    if (parts & kRecoverEnergy) {
      out.energy.kinetic += 0.5 * model.mass[i] * v.squaredNorm() + 0.5 * w.dot(inertia * w);
      out.energy.potential -= model.mass[i] * model.gravity.dot(r);
      for (const BodyPointForce& f : model.point_forces[i]) out.energy.potential -= f.force.dot(r + A * f.point);
      out.energy.spring += data.spring_energy[i];
    }
    if (parts & kRecoverAngularMomentum)
      out.angular_momentum_about_base += model.mass[i] * (r - data.base.position).cross(v) + inertia * w;
  }
}

}  // namespace

void recover(const Model& model, const Data& data, Recovered& out, unsigned parts) {
  const auto size = static_cast<std::size_t>(model.n);
  out.rotation.resize(size);
  for (auto* v : {&out.angular_velocity, &out.angular_acceleration, &out.com_position, &out.com_velocity,
                  &out.com_acceleration, &out.joint_position, &out.joint_reaction, &out.joint_axis, &out.joint_moment})
    v->resize(size, Vec3::Zero());
  out.joint_angle.resize(size, 0.0);
  out.time = data.time;
  out.base = data.base;
  out.energy = Energies{};
  out.angular_momentum_about_base.setZero();
  recover_points(model, data, out, (parts & kRecoverAccelerations) != 0);
  if (parts & (kRecoverJointAngles | kRecoverEnergy | kRecoverAngularMomentum)) recover_totals(model, data, out, parts);
}

Vec3 body_point_position(const Recovered& r, int user_body, const Vec3& point) {
  return r.com_position[user_body] + r.rotation[user_body] * point;
}

}  // namespace treedyn
