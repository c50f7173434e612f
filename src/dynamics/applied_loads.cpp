// Force stage.
#include "dynamics/joint_spring.hpp"
#include "dynamics/pipeline.hpp"

namespace treedyn {

void compute_applied_loads(const Model& model, Data& data) {
  const int n = model.n;
  data.base = model.base_motion.at(data.time);
  for (int i = 0; i < n; ++i) {
    data.force[i] = model.mass[i] * model.gravity;
    data.moment[i] = model.applied_moment[i];
  }
  if (model.has_point_forces) {
    for (int i = 0; i < n; ++i) {
      for (const BodyPointForce& f : model.point_forces[i]) {
        data.force[i] += f.force;
        data.moment[i] += (data.rotation[i] * f.point).cross(f.force);
      }
    }
  }
  for (int k = 0; k < n; ++k) data.subtree_force[k] = data.force[k];
  for (int k = n - 1; k >= 1; --k) data.subtree_force[model.tree().parent[k]] += data.subtree_force[k];

  for (int a = 0; a < n; ++a) {
    if (!model.has_spring[a]) {
      data.joint_moment[a].setZero();
      data.spring_energy[a] = 0.0;
      continue;
    }
    const int p = model.tree().parent[a];
    const JointLoad load =
        p == kBase ? joint_spring_load(model.spring[a], Mat3::Identity(), data.rotation[a],
                                       Vec3::Zero(), data.angular_velocity[a])
                   : joint_spring_load(model.spring[a], data.rotation[p], data.rotation[a],
                                       data.angular_velocity[p], data.angular_velocity[a]);
    data.joint_moment[a] = load.moment;
    data.spring_energy[a] = load.energy;
  }
}

}  // namespace treedyn
