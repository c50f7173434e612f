// Acceleration stage, parts 2 and 3: the mass matrix K of docs/wittenburg.md, section 4 in its
// branch-induced sparsity, factored K = L^T D L without fill-in (Featherstone's
// LTDL in 3x3 blocks, children after parents), then w' = K^-1 Q.
#include <algorithm>
#include <string>

#include "common/error.hpp"
#include "dynamics/pipeline.hpp"

namespace treedyn {

long long path_block_count(const Topology& tree) {
  long long blocks = 0;
  for (int d : tree.depth) blocks += d - 1;
  return blocks;
}

void require_sparse_factor_fits(const Topology& tree) {
  const long long blocks = path_block_count(tree);
  if (blocks > kMaxPathBlocks)
    throw ModelError(
        "model: the tree is too deep for treedyn: " + std::to_string(blocks) + " (body, ancestor) pairs, at most " +
        std::to_string(kMaxPathBlocks) +
        " (a single chain of about 3100 bodies) for solver \"sparse_ldlt\"; use solver = \"recursive\" (the default)");
}

SparseMassMatrix::SparseMassMatrix(const Topology& tree) {
  require_sparse_factor_fits(tree);
  const auto n = static_cast<std::size_t>(tree.n);
  path_offset.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) path_offset[i + 1] = path_offset[i] + tree.depth[i] - 1;
  diagonal_block.assign(n, Mat3::Zero());
  // A default LLT leaves its status uninitialised, and copying it reads that
  // (undefined behaviour, found by UBSan): copy a factored identity instead.
  diagonal_factor.assign(n, Eigen::LLT<Mat3>(Mat3::Identity()));
  path_block.assign(static_cast<std::size_t>(path_offset.back()), Mat3::Zero());
  const int max_depth = *std::max_element(tree.depth.begin(), tree.depth.end());
  scratch_path.assign(static_cast<std::size_t>(max_depth), Mat3::Zero());
}

namespace {

// K_{k a} for a strict ancestor a of k, whose child on the path to k is `branch`:
// M ((d_ak . b_k0) E - d_ak b_k0^T) (section 4, j < i).
Mat3 path_coupling(const Model& model, const Data& data, int k, int branch) {
  // The transpose of K_{a k} = M ((b . d) E - b d^T), the matrix of w' -> d x (w' x b).
  return model.total_mass * cross_cross_matrix(data.branch_d[branch], data.barycentre_to_inboard[k]).transpose();
}

void assemble(const Model& model, Data& data) {
  const Topology& tree = model.tree();
  SparseMassMatrix& K = data.mass_matrix;
  for (int k = 0; k < model.n; ++k) {
    K.diagonal_block[k] = data.augmented_inertia[k];
    int slot = K.path_offset[k];
    for (int branch = k, a = tree.parent[k]; a != kBase; branch = a, a = tree.parent[a])
      K.path_block[slot++] = path_coupling(model, data, k, branch);
  }
}

}  // namespace

bool factor_mass_matrix(const Model& model, Data& data) {
  assemble(model, data);
  const Topology& tree = model.tree();
  SparseMassMatrix& K = data.mass_matrix;
  for (int k = model.n - 1; k >= 0; --k) {
    auto& factor = K.diagonal_factor[k];
    factor.compute(K.diagonal_block[k]);
    if (factor.info() != Eigen::Success) return false;
    const int offset = K.path_offset[k];
    const int levels = tree.depth[k] - 1;
    for (int l = 0; l < levels; ++l) K.scratch_path[l] = factor.solve(K.path_block[offset + l]);
    // Eliminate k: block (a, b) -= K_{k a}^T L_{k b} for ancestors a, b of k
    // with b an ancestor of a or a itself.
    int a = tree.parent[k];
    for (int la = 0; la < levels; ++la, a = tree.parent[a]) {
      const Mat3 coupling_t = K.path_block[offset + la].transpose();
      K.diagonal_block[a].noalias() -= coupling_t * K.scratch_path[la];
      const int a_offset = K.path_offset[a];
      for (int lb = la + 1; lb < levels; ++lb)
        K.path_block[a_offset + (lb - la - 1)].noalias() -= coupling_t * K.scratch_path[lb];
    }
    for (int l = 0; l < levels; ++l) K.path_block[offset + l] = K.scratch_path[l];
  }
  return true;
}

void solve_angular_accelerations(const Model& model, Data& data) {
  const Topology& tree = model.tree();
  const SparseMassMatrix& K = data.mass_matrix;
  Eigen::VectorXd& x = data.angular_acceleration;
  x = data.generalised_force;
  // L^T y = Q: descendants (larger indices) finish before their ancestors.
  for (int k = model.n - 1; k >= 0; --k) {
    const Vec3 y = x.segment<3>(3 * k);
    int slot = K.path_offset[k];
    for (int a = tree.parent[k]; a != kBase; a = tree.parent[a])
      x.segment<3>(3 * a).noalias() -= K.path_block[slot++].transpose() * y;
  }
  for (int k = 0; k < model.n; ++k) x.segment<3>(3 * k) = K.diagonal_factor[k].solve(Vec3(x.segment<3>(3 * k)));
  // L w' = z: ancestors (smaller indices) first.
  for (int k = 0; k < model.n; ++k) {
    Vec3 sum = Vec3::Zero();
    int slot = K.path_offset[k];
    for (int a = tree.parent[k]; a != kBase; a = tree.parent[a])
      sum.noalias() += K.path_block[slot++] * x.segment<3>(3 * a);
    x.segment<3>(3 * k) -= sum;
  }
}

Eigen::MatrixXd dense_mass_matrix(const Model& model, const Data& data) {
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(3 * model.n, 3 * model.n);
  const Topology& tree = model.tree();
  for (int k = 0; k < model.n; ++k) {
    K.block<3, 3>(3 * k, 3 * k) = data.augmented_inertia[k];
    for (int branch = k, a = tree.parent[k]; a != kBase; branch = a, a = tree.parent[a]) {
      const Mat3 block = path_coupling(model, data, k, branch);
      K.block<3, 3>(3 * k, 3 * a) = block;
      K.block<3, 3>(3 * a, 3 * k) = block.transpose();
    }
  }
  return K;
}

}  // namespace treedyn
