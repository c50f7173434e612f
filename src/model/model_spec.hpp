// The user's description of a tree system, in the user's names and order.
// Nothing here is validated; build_model() checks it and relabels it.
#pragma once

#include <string>
#include <vector>

#include "common/linalg.hpp"
#include "model/base_motion.hpp"

namespace treedyn {

// The name a joint's parent takes when the joint attaches to body 0.
inline constexpr const char* kBaseName = "base";

struct BodySpec {
  std::string name;
  double mass = 0.0;                  // kg
  Mat3 inertia = Mat3::Identity();    // central inertia tensor in the body frame, kg m^2
};

// Central inertia from principal moments and the principal axes (columns of
// `axes`, a rotation matrix, expressed in the body frame).
Mat3 inertia_from_principal(const Vec3& moments, const Mat3& axes = Mat3::Identity());

// Linear spring-damper on the relative rotation of a joint's two bodies.
// The law is smooth on all of SO(3): with q = (q0, e) the unit quaternion of the
// deviation from `reference`, the potential is V = 2 e^T K e (= k (1 - cos angle)
// for isotropic K = k E), whose moment is -K * angle * axis for small angles and
// falls back to zero, never flipping, at 180 degrees. Stiffness and damping act
// in the child's frame.
struct JointSpring {
  Mat3 stiffness = Mat3::Zero();        // N m / rad, symmetric positive semi-definite
  Mat3 damping = Mat3::Zero();          // N m s / rad, symmetric positive semi-definite
  Quat reference = Quat::Identity();    // unloaded orientation of child relative to parent
};

struct JointSpec {
  std::string name;                   // optional; defaults to "<parent>-<child>"
  std::string parent;                 // a body name, or kBaseName
  std::string child;                  // a body name
  Vec3 on_parent = Vec3::Zero();      // joint point from the parent's CoM, parent frame
                                      // (for the base joint: r0 is the point itself; ignored)
  Vec3 on_child = Vec3::Zero();       // joint point from the child's CoM, child frame
  JointSpring spring;
};

// A constant force (inertial frame) applied at a point fixed in a body
// (from its CoM, body frame).
struct PointForce {
  std::string body;
  Vec3 point = Vec3::Zero();
  Vec3 force = Vec3::Zero();
};

// A constant moment (inertial frame) on a body.
struct BodyMoment {
  std::string body;
  Vec3 moment = Vec3::Zero();
};

struct ModelSpec {
  std::vector<BodySpec> bodies;
  std::vector<JointSpec> joints;          // one per body: joint a connects child a to its parent
  Vec3 gravity{0.0, 0.0, -9.81};          // m/s^2
  BaseMotionSpec base_motion = FixedBase{};
  std::vector<PointForce> forces;
  std::vector<BodyMoment> moments;
};

}  // namespace treedyn
