// Acceleration stage, parts 2 and 3: the mass matrix K of section 4 in its
// branch-induced sparsity, factored K = L^T D L without fill-in (Featherstone's
// LTDL in 3x3 blocks, children after parents), then w' = K^-1 Q.
#include "dynamics/pipeline.hpp"

namespace treedyn {
namespace {

// K_{k a} for a strict ancestor a of k, whose child on the path to k is `branch`:
// M ((d_ak . b_k0) E - d_ak b_k0^T) (section 4, j < i).
Mat3 path_coupling(const Model& model, const Data& data, int k, int branch) {
  // The transpose of K_{a k} = M ((b . d) E - b d^T), the matrix of w' -> d x (w' x b).
  return model.total_mass *
         cross_cross_matrix(data.branch_d[branch], data.barycentre_to_inboard[k]).transpose();
}

void assemble(const Model& model, Data& data) {
  for (int k = 0; k < model.n; ++k) {
    data.diagonal_block[k] = data.augmented_inertia[k];
    int slot = model.path_offset[k];
    for (int branch = k, a = model.parent[k]; a != kBase; branch = a, a = model.parent[a])
      data.path_block[slot++] = path_coupling(model, data, k, branch);
  }
}

}  // namespace

bool factor_mass_matrix(const Model& model, Data& data) {
  assemble(model, data);
  for (int k = model.n - 1; k >= 0; --k) {
    auto& factor = data.diagonal_factor[k];
    factor.compute(data.diagonal_block[k]);
    if (factor.info() != Eigen::Success) return false;
    const int offset = model.path_offset[k];
    const int levels = model.depth[k] - 1;
    for (int l = 0; l < levels; ++l) data.scratch_path[l] = factor.solve(data.path_block[offset + l]);
    // Eliminate k: block (a, b) -= K_{k a}^T L_{k b} for ancestors a, b of k
    // with b an ancestor of a or a itself.
    int a = model.parent[k];
    for (int la = 0; la < levels; ++la, a = model.parent[a]) {
      const Mat3 coupling_t = data.path_block[offset + la].transpose();
      data.diagonal_block[a].noalias() -= coupling_t * data.scratch_path[la];
      const int a_offset = model.path_offset[a];
      for (int lb = la + 1; lb < levels; ++lb)
        data.path_block[a_offset + (lb - la - 1)].noalias() -= coupling_t * data.scratch_path[lb];
    }
    for (int l = 0; l < levels; ++l) data.path_block[offset + l] = data.scratch_path[l];
  }
  return true;
}

void solve_angular_accelerations(const Model& model, Data& data) {
  Eigen::VectorXd& x = data.angular_acceleration;
  x = data.generalised_force;
  // L^T y = Q: descendants (larger indices) finish before their ancestors.
  for (int k = model.n - 1; k >= 0; --k) {
    const Vec3 y = x.segment<3>(3 * k);
    int slot = model.path_offset[k];
    for (int a = model.parent[k]; a != kBase; a = model.parent[a])
      x.segment<3>(3 * a).noalias() -= data.path_block[slot++].transpose() * y;
  }
  for (int k = 0; k < model.n; ++k)
    x.segment<3>(3 * k) = data.diagonal_factor[k].solve(Vec3(x.segment<3>(3 * k)));
  // L w' = z: ancestors (smaller indices) first.
  for (int k = 0; k < model.n; ++k) {
    Vec3 sum = Vec3::Zero();
    int slot = model.path_offset[k];
    for (int a = model.parent[k]; a != kBase; a = model.parent[a])
      sum.noalias() += data.path_block[slot++] * x.segment<3>(3 * a);
    x.segment<3>(3 * k) -= sum;
  }
}

Eigen::MatrixXd dense_mass_matrix(const Model& model, const Data& data) {
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(3 * model.n, 3 * model.n);
  for (int k = 0; k < model.n; ++k) {
    K.block<3, 3>(3 * k, 3 * k) = data.augmented_inertia[k];
    for (int branch = k, a = model.parent[k]; a != kBase; branch = a, a = model.parent[a]) {
      const Mat3 block = path_coupling(model, data, k, branch);
      K.block<3, 3>(3 * k, 3 * a) = block;
      K.block<3, 3>(3 * a, 3 * k) = block.transpose();
    }
  }
  return K;
}

}  // namespace treedyn
