// The joint spring-damper laws (SpringLaw in model/model_spec.hpp).
#pragma once

#include "common/linalg.hpp"
#include "model/model_spec.hpp"

namespace treedyn {

struct JointLoad {
  Vec3 moment = Vec3::Zero();  // Y_a on the child, inertial frame (reversed on the parent)
  double energy = 0.0;         // spring potential V of the law
};

// A_parent = identity and w_parent = 0 for the joint on the base. `spring`
// as in a Model: symmetric matrices, unit reference quaternion.
JointLoad joint_spring_load(const JointSpring& spring, const Mat3& A_parent, const Mat3& A_child, const Vec3& w_parent,
                            const Vec3& w_child);

}  // namespace treedyn
