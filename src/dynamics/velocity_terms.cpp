// Velocity stage: the two centripetal sums of (55), each in O(n).
#include "dynamics/pipeline.hpp"

namespace treedyn {

void compute_velocity_terms(const Model& model, Data& data) {
  const int n = model.n;
  for (int j = 0; j < n; ++j) {
    const Vec3& w = data.angular_velocity[j];
    data.centripetal_b[j] = w.cross(w.cross(data.barycentre_to_inboard[j]));
  }
  // Sum of w_j x (w_j x b_j0) over sub(k): children have larger indices.
  for (int k = n - 1; k >= 0; --k) data.subtree_centripetal_b[k] = data.centripetal_b[k];
  for (int k = n - 1; k >= 1; --k) data.subtree_centripetal_b[model.tree().parent[k]] += data.subtree_centripetal_b[k];
  // Sum over strict ancestors j of i of w_j x (w_j x d_ji); d_ji is the branch
  // vector of the child of j on the path to i.
  for (int i = 0; i < n; ++i) {
    const int p = model.tree().parent[i];
    if (p == kBase) {
      data.ancestor_centripetal_d[i].setZero();
    } else {
      const Vec3& w = data.angular_velocity[p];
      data.ancestor_centripetal_d[i] = data.ancestor_centripetal_d[p] + w.cross(w.cross(data.branch_d[i]));
    }
  }
}

}  // namespace treedyn
