// The tree's shape, fixed once a job is read: which body hangs from which,
// the regular order of docs/wittenburg.md (parent p(a) < a, body 0 = base;
// depth-first preorder, so every subtree is a contiguous index range), and the
// names. Immutable; every Model derived from one job shares it.
#pragma once

#include <string>
#include <vector>

#include "model/model_spec.hpp"

namespace treedyn {

inline constexpr int kBase = -1;  // parent index of body 1 (the lecture's body 0)

// Indices are in the regular order, 0-based: index i is the lecture's body
// i+1, and joint i is the joint whose outboard body is i. "User index" is the
// position in ModelSpec::bodies (the job file's order).
struct Topology {
  int n = 0;                               // number of bodies
  std::vector<int> parent;                 // p(i), kBase for the root
  std::vector<std::vector<int>> children;  // bodies k with p(k) = i, ascending
  std::vector<int> depth;                  // number of joints from the base to i
  std::vector<int> user_index;             // regular -> user
  std::vector<int> regular_index;          // user -> regular
  std::vector<int> joint_of_user_body;     // user body -> index in ModelSpec::joints
  std::vector<std::string> body_name;      // regular order
  std::vector<std::string> joint_name;     // regular order (joint i: parent -> i)

  bool is_ancestor(int i, int j) const;  // i < j in the lecture's notation
  const std::string& user_body_name(int user) const { return body_name[regular_index[user]]; }
  // User index of the body with this name, or -1.
  int find_user_body(const std::string& name) const;
};

// Throws ModelError naming the body or joint when the bodies' names are not
// unique, or the joints do not form a tree with exactly one body on the base.
Topology make_topology(const ModelSpec& spec);

}  // namespace treedyn
