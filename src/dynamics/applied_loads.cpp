// Force stage.
#include "dynamics/joint_spring.hpp"
#include "dynamics/pipeline.hpp"

namespace treedyn {

void compute_body_loads(const Model& model, Data& data, int i) {
  data.force[i] = model.mass[i] * model.gravity;
  data.moment[i] = model.applied_moment[i];
  if (model.has_point_forces) {
    for (const BodyPointForce& f : model.point_forces[i]) {
      data.force[i] += f.force;
      data.moment[i] += (data.rotation[i] * f.point).cross(f.force);
    }
  }
  if (!model.has_spring[i]) {
    data.joint_moment[i].setZero();
    data.spring_energy[i] = 0.0;
    return;
  }
  const int p = model.tree().parent[i];
  const JointLoad load = p == kBase ? joint_spring_load(model.spring[i], Mat3::Identity(), data.rotation[i],
                                                        Vec3::Zero(), data.angular_velocity[i])
                                    : joint_spring_load(model.spring[i], data.rotation[p], data.rotation[i],
                                                        data.angular_velocity[p], data.angular_velocity[i]);
  data.joint_moment[i] = load.moment;
  data.spring_energy[i] = load.energy;
}

void compute_applied_loads(const Model& model, Data& data) {
  const int n = model.n;
  data.base = model.base_motion.at(data.time);
  for (int i = 0; i < n; ++i) compute_body_loads(model, data, i);
  for (int k = 0; k < n; ++k) data.subtree_force[k] = data.force[k];
  for (int k = n - 1; k >= 1; --k) data.subtree_force[model.tree().parent[k]] += data.subtree_force[k];
}

}  // namespace treedyn
