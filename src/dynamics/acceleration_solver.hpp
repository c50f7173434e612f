// Which acceleration stage solves for w': the O(n) recursion of section 8 of
// docs/wittenburg.md, or the tree-sparse L^T D L of K (section 4, eq. 59). Both
// read the same position, velocity and force stages and give the same w'.
#pragma once

#include <string_view>

#include "common/enum_names.hpp"

namespace treedyn {

enum class AccelerationSolver {
  automatic,    // chosen by resolve_solver()
  recursive,    // articulated 3x3 masses, two sweeps, O(n) for any tree
  sparse_ldlt,  // K assembled and factored without fill-in, O(sum of depths^2) for a chain
};

inline constexpr NameTable<AccelerationSolver, 3> kAccelerationSolverNames{
    {{AccelerationSolver::automatic, "auto"},
     {AccelerationSolver::recursive, "recursive"},
     {AccelerationSolver::sparse_ldlt, "sparse_ldlt"}}};
inline std::string_view name(AccelerationSolver s) { return name_in(kAccelerationSolverNames, s); }
inline bool parse_acceleration_solver(std::string_view text, AccelerationSolver& out) {
  return parse_in(kAccelerationSolverNames, text, out);
}

// "auto" is the recursive solver: it is faster at every size measured
// (BENCHMARKS.md, from one body up) and has no depth limit. The others stay.
constexpr AccelerationSolver resolve_solver(AccelerationSolver requested) {
  return requested == AccelerationSolver::automatic ? AccelerationSolver::recursive : requested;
}

}  // namespace treedyn
