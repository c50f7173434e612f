// One physical model: the shared, immutable tree plus everything a parameter
// vector fixes (masses, inertias, joint points, springs, loads, base motion)
// and the body-frame constants of section 3 of docs/wittenburg.md derived from
// them. Built by derive_model() (model/definition.hpp) and not changed while
// a trajectory runs; the solver's workspace lives in Data, not here.
#pragma once

#include <memory>
#include <vector>

#include "common/linalg.hpp"
#include "model/base_motion.hpp"
#include "model/model_spec.hpp"
#include "model/topology.hpp"

namespace treedyn {

// A constant force (inertial frame) at a point fixed in a body (from its CoM,
// body frame).
struct BodyPointForce {
  Vec3 point = Vec3::Zero();
  Vec3 force = Vec3::Zero();
};

// Everything per body or joint is in the regular order of the topology.
struct Model {
  std::shared_ptr<const Topology> topology;
  int n = 0;  // number of bodies
  const Topology& tree() const { return *topology; }

  // Inertial data.
  std::vector<double> mass;          // m_i
  std::vector<Mat3> inertia;         // J_i, central, body frame
  double total_mass = 0.0;           // M = mu_1
  std::vector<double> subtree_mass;  // mu_i

  // Body-frame constants of section 3.
  std::vector<Vec3> com_to_inboard_joint;   // c_ii (= d_ii)
  std::vector<Vec3> parent_com_to_joint;    // c_{p(i) i}: joint i on its parent, parent frame
  std::vector<Vec3> branch_d;               // d_{p(k) j} for j in sub(k): c_pp - c_pk, parent frame
  std::vector<Vec3> barycentre;             // beta_i, from the CoM of i
  std::vector<Vec3> barycentre_to_inboard;  // b_i0 = c_ii - beta_i (38)
  std::vector<Mat3> augmented_inertia;      // K_i about the inboard joint (47)-(48)
  std::vector<Mat3> inertia_about_joint;    // J_i - m_i [c_ii]x^2: body i alone about its inboard joint

  // Applied loads and joint laws.
  Vec3 gravity = Vec3::Zero();
  BaseMotion base_motion;
  std::vector<JointSpring> spring;                        // joint i's spring-damper (symmetrised, unit reference)
  std::vector<char> has_spring;                           // stiffness or damping non-zero
  std::vector<std::vector<BodyPointForce>> point_forces;  // per body
  std::vector<Vec3> applied_moment;                       // constant external moment per body, inertial
  bool has_point_forces = false;
};

// The nominal model of a description: define_model() then derive_model()
// with the nominal parameters. Throws ModelError naming the offending body or
// joint.
Model build_model(const ModelSpec& spec);

}  // namespace treedyn
