// Storage of the tree-sparse factorisation K = L^T D L of the mass matrix of
// docs/wittenburg.md, section 4: one 3x3 block per body (its diagonal) and one per (body, strict
// ancestor) pair, the only non-zero blocks (no fill-in). Its layout depends
// on the tree alone.
#pragma once

#include <Eigen/Cholesky>

#include <vector>

#include "common/linalg.hpp"
#include "model/topology.hpp"

namespace treedyn {

// Largest number of (body, strict ancestor) pairs: the blocks (72 bytes
// each, 360 MB here) and a dense chain's O(n^3) factorisation bound what is
// sensible.
inline constexpr long long kMaxPathBlocks = 5'000'000;

// Sum over the bodies of (depth - 1).
long long path_block_count(const Topology& tree);
// Throws ModelError when the tree needs more than kMaxPathBlocks blocks.
void require_sparse_factor_fits(const Topology& tree);

struct SparseMassMatrix {
  SparseMassMatrix() = default;                     // empty: not the solver in use
  explicit SparseMassMatrix(const Topology& tree);  // throws ModelError when too deep

  std::vector<int> path_offset;      // start of body i's strict-ancestor blocks
                                     // (sum of depth - 1 before i); n + 1 entries
  std::vector<Mat3> diagonal_block;  // K_ii, then D_i
  std::vector<Eigen::LLT<Mat3>> diagonal_factor;
  std::vector<Mat3> path_block;    // K_{k,a} for a strict ancestor of k, then L_{k,a}
  std::vector<Mat3> scratch_path;  // one path's L while it is formed
};

}  // namespace treedyn
