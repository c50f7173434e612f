// Position stage.
#include "dynamics/pipeline.hpp"

namespace treedyn {

void compute_frame_vectors(const Model& model, Data& data) {
  for (int i = 0; i < model.n; ++i) {
    const Mat3& A = data.rotation[i];
    data.augmented_inertia[i].noalias() = A * model.augmented_inertia[i] * A.transpose();
    data.barycentre_to_inboard[i].noalias() = A * model.barycentre_to_inboard[i];
    data.com_to_inboard_joint[i].noalias() = A * model.com_to_inboard_joint[i];
    const int p = model.tree().parent[i];
    if (p != kBase) data.branch_d[i].noalias() = data.rotation[p] * model.branch_d[i];
  }
}

}  // namespace treedyn
