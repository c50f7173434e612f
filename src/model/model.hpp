// The validated, immutable tree: bodies relabelled into the regular order of
// the theory page (parent p(a) < a, body 0 = base), with the body-frame
// constants of section 3 precomputed once.
#pragma once

#include <string>
#include <vector>

#include "common/linalg.hpp"
#include "model/base_motion.hpp"
#include "model/model_spec.hpp"

namespace treedyn {

inline constexpr int kBase = -1;  // parent index of body 1 (the lecture's body 0)
// Largest number of (body, strict ancestor) pairs: the mass matrix's blocks
// (72 bytes each, 360 MB here) and a dense chain's O(n^3) factorisation bound
// what is sensible.
inline constexpr long long kMaxPathBlocks = 5'000'000;

// Everything below is in the regular order, 0-based: index i is the lecture's
// body i+1, and joint i is the joint whose outboard body is i.
struct Model {
  int n = 0;                                  // number of bodies
  std::vector<int> parent;                    // p(i), kBase for the root
  std::vector<std::vector<int>> children;     // bodies k with p(k) = i, ascending
  std::vector<int> depth;                     // number of joints from the base to i
  std::vector<int> path_offset;               // start of body i's strict-ancestor blocks
                                              // in a flat array (sum of depth - 1 before i)
  std::vector<int> user_index;                // regular index -> index in ModelSpec::bodies
  std::vector<int> regular_index;             // index in ModelSpec::bodies -> regular index
  std::vector<std::string> body_name;         // regular order
  std::vector<std::string> joint_name;        // regular order (joint i: parent -> i)

  // Inertial data.
  std::vector<double> mass;                   // m_i
  std::vector<Mat3> inertia;                  // J_i, central, body frame
  double total_mass = 0.0;                    // M = mu_1
  std::vector<double> subtree_mass;           // mu_i

  // Body-frame constants of section 3.
  std::vector<Vec3> com_to_inboard_joint;     // c_ii (= d_ii)
  std::vector<Vec3> parent_com_to_joint;      // c_{p(i) i}: joint i on its parent, parent frame
  std::vector<Vec3> branch_d;                 // d_{p(k) j} for j in sub(k): c_pp - c_pk, parent frame
  std::vector<Vec3> barycentre;               // beta_i, from the CoM of i
  std::vector<Vec3> barycentre_to_inboard;    // b_i0 = c_ii - beta_i (38)
  std::vector<Mat3> augmented_inertia;        // K_i about the inboard joint (47)-(48)

  // Applied loads and joint laws (regular order).
  Vec3 gravity = Vec3::Zero();
  BaseMotion base_motion;
  std::vector<JointSpring> spring;            // joint i's spring-damper
  std::vector<bool> has_spring;               // stiffness or damping non-zero
  std::vector<std::vector<PointForce>> point_forces;  // per body (body field unused)
  std::vector<Vec3> applied_moment;           // constant external moment per body, inertial
  bool has_point_forces = false;

  ModelSpec spec;                             // what the user gave, for reports

  bool is_ancestor(int i, int j) const;       // i < j in the lecture's notation
};

// Validates and relabels; throws ModelError naming the offending body or joint.
Model build_model(const ModelSpec& spec);

}  // namespace treedyn
