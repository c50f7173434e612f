// Acceleration stage, part 1: Q_i = Mstar_i + M_i + Y_i - sum_k Y_k (59), with
// Mstar_i of (55).
#include "dynamics/pipeline.hpp"

namespace treedyn {

void compute_generalised_forces(const Model& model, Data& data) {
  const double M = model.total_mass;
  for (int i = 0; i < model.n; ++i) {
    const Vec3& w = data.angular_velocity[i];
    const Vec3& b_i0 = data.barycentre_to_inboard[i];
    Vec3 q = -w.cross(data.augmented_inertia[i] * w);        // gyroscopic
    q -= M * b_i0.cross(data.ancestor_centripetal_d[i]);     // from ancestors j < i
    q += M * b_i0.cross(data.base.acceleration);             // base acceleration r0''
    q -= data.com_to_inboard_joint[i].cross(data.force[i]);  // d_ii x F_i
    for (int k : model.tree().children[i]) {
      q -= M * data.branch_d[k].cross(data.subtree_centripetal_b[k]);  // from descendants j > i
      q -= data.branch_d[k].cross(data.subtree_force[k]);              // d_ij x F_j, j in sub(k)
      q -= data.joint_moment[k];                                       // -Y_k on the parent
    }
    q += data.moment[i] + data.joint_moment[i];
    data.generalised_force.segment<3>(3 * i) = q;
  }
}

}  // namespace treedyn
