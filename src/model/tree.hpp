// Tree topology: checks that the joints form a tree hung from the base and
// relabels the bodies into the regular order (p(a) < a, depth-first preorder so
// every subtree is a contiguous index range).
#pragma once

#include <vector>

#include "model/model_spec.hpp"

namespace treedyn {

struct Topology {
  std::vector<int> parent;                  // regular order, kBase for the root
  std::vector<std::vector<int>> children;   // regular order
  std::vector<int> depth;
  std::vector<int> user_index;              // regular -> user body index
  std::vector<int> regular_index;           // user body index -> regular
  std::vector<int> joint_of_user_body;      // user body index -> index in ModelSpec::joints
};

// Throws ModelError naming the body or joint when the joints do not form a tree
// with exactly one body on the base.
Topology regular_order(const ModelSpec& spec);

}  // namespace treedyn
