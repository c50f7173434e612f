#include "dynamics/recovered.hpp"

#include <cmath>

namespace treedyn {

Recovered recover(const Model& model, const Data& data) {
  const int n = model.n;
  Recovered out;
  out.time = data.time;
  out.base = data.base;
  // Regular order first, top-down: each CoM from its inboard joint point (20).
  std::vector<Vec3> r(n), v(n), acc(n), joint(n), wdot(n);
  for (int i = 0; i < n; ++i) {
    const int p = model.parent[i];
    const Vec3& w = data.angular_velocity[i];
    wdot[i] = data.angular_acceleration.segment<3>(3 * i);
    Vec3 jp = data.base.position, jv = data.base.velocity, ja = data.base.acceleration;
    if (p != kBase) {
      const Vec3 arm = data.rotation[p] * model.parent_com_to_joint[i];
      const Vec3& wp = data.angular_velocity[p];
      jp = r[p] + arm;
      jv = v[p] + wp.cross(arm);
      ja = acc[p] + wdot[p].cross(arm) + wp.cross(wp.cross(arm));
    }
    const Vec3& c = data.com_to_inboard_joint[i];
    joint[i] = jp;
    r[i] = jp - c;
    v[i] = jv - w.cross(c);
    acc[i] = ja - wdot[i].cross(c) - w.cross(w.cross(c));
  }
  // X_a = sum over sub(a) of m_i r_i'' - F_i (12), bottom-up.
  std::vector<Vec3> reaction(n);
  for (int i = 0; i < n; ++i) reaction[i] = model.mass[i] * acc[i] - data.force[i];
  for (int i = n - 1; i >= 1; --i) reaction[model.parent[i]] += reaction[i];

  out.rotation.resize(n);
  out.angular_velocity.resize(n);
  out.angular_acceleration.resize(n);
  out.com_position.resize(n);
  out.com_velocity.resize(n);
  out.com_acceleration.resize(n);
  out.joint_position.resize(n);
  out.joint_reaction.resize(n);
  out.joint_angle.resize(n);
  out.joint_axis.resize(n);
  out.joint_moment.resize(n);
  for (int i = 0; i < n; ++i) {
    const int u = model.user_index[i];
    const Mat3& A = data.rotation[i];
    const Vec3& w = data.angular_velocity[i];
    out.rotation[u] = A;
    out.angular_velocity[u] = w;
    out.angular_acceleration[u] = wdot[i];
    out.com_position[u] = r[i];
    out.com_velocity[u] = v[i];
    out.com_acceleration[u] = acc[i];
    out.joint_position[u] = joint[i];
    out.joint_reaction[u] = reaction[i];
    out.joint_moment[u] = data.joint_moment[i];
    const int p = model.parent[i];
    const Mat3 relative = p == kBase ? A : Mat3(data.rotation[p].transpose() * A);
    const Eigen::AngleAxisd aa(relative);
    out.joint_angle[u] = aa.angle();
    out.joint_axis[u] = aa.angle() > 0.0 ? Vec3(aa.axis()) : Vec3::Zero();

    const Mat3 inertia = A * model.inertia[i] * A.transpose();
    out.energy.kinetic += 0.5 * model.mass[i] * v[i].squaredNorm() + 0.5 * w.dot(inertia * w);
    out.energy.potential -= model.mass[i] * model.gravity.dot(r[i]);
    for (const PointForce& f : model.point_forces[i])
      out.energy.potential -= f.force.dot(r[i] + A * f.point);
    out.energy.spring += data.spring_energy[i];
    out.angular_momentum_about_base +=
        model.mass[i] * (r[i] - data.base.position).cross(v[i]) + inertia * w;
  }
  return out;
}

Vec3 body_point_position(const Recovered& r, int user_body, const Vec3& point) {
  return r.com_position[user_body] + r.rotation[user_body] * point;
}

Vec3 body_point_velocity(const Recovered& r, int user_body, const Vec3& point) {
  return r.com_velocity[user_body] +
         r.angular_velocity[user_body].cross(r.rotation[user_body] * point);
}

}  // namespace treedyn
