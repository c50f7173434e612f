// The user's description of a tree system, in the user's names and order, as
// a job file (or a test) gives it. Nothing here is validated: define_model()
// checks the tree and names its parameters, derive_model() checks the physics.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/enum_names.hpp"
#include "common/linalg.hpp"
#include "model/base_motion.hpp"

namespace treedyn {

// The name a joint's parent takes when the joint attaches to body 0.
inline constexpr const char* kBaseName = "base";

// A homogeneous solid whose inertia follows from its mass and dimensions
// (model/solids.hpp), centre of mass at its centre.
enum class Solid {
  none,      // the inertia is given explicitly
  box,       // edges `size` along body x, y, z
  cylinder,  // `radius`, `length`, axis along body z
  sphere,    // `radius`
};
inline constexpr NameTable<Solid, 3> kSolidNames{
    {{Solid::box, "box"}, {Solid::cylinder, "cylinder"}, {Solid::sphere, "sphere"}}};

struct BodySpec {
  std::string name;
  double mass = 0.0;                // kg; unused for a solid given by its density
  Mat3 inertia = Mat3::Identity();  // central inertia, body frame, kg m^2 (Solid::none only)
  Solid solid = Solid::none;
  Vec3 size = Vec3::Zero();       // box edges, m
  double radius = 0.0;            // cylinder, sphere, m
  double length = 0.0;            // cylinder, m
  std::optional<double> density;  // kg/m^3: a solid given by density instead of mass
};

// A body with an explicit mass and central inertia.
inline BodySpec rigid_body(std::string name, double mass, const Mat3& inertia) {
  BodySpec b;
  b.name = std::move(name);
  b.mass = mass;
  b.inertia = inertia;
  return b;
}

// Central inertia from principal moments and the principal axes (columns of
// `axes`, a rotation matrix, expressed in the body frame).
Mat3 inertia_from_principal(const Vec3& moments, const Mat3& axes = Mat3::Identity());

// How a joint's spring turns the relative rotation into a moment. Both act on
// the deviation D = R_ref^T R_rel of the child from its reference orientation
// relative to the parent; K is the stiffness in the child's frame.
enum class SpringLaw {
  // V = 2 e^T K e with q = (q0, e) the unit quaternion of D (= k (1 - cos angle)
  // for K = k E). Moment -K angle axis for small angles, k sin(angle) in size
  // for K = k E; smooth on all of SO(3): it falls to zero at 180 degrees
  // instead of flipping.
  quaternion,
  // V = theta^T K theta / 2 with theta = angle axis the rotation vector of D
  // (angle in [0, pi]). Moment -K theta for K = k E (MuJoCo's ball joint),
  // linear in the angle; for anisotropic K the exact gradient of V. At 180
  // degrees theta jumps to -theta: the moment (k pi) reverses direction.
  rotation_vector,
};
inline constexpr NameTable<SpringLaw, 2> kSpringLawNames{
    {{SpringLaw::quaternion, "quaternion"}, {SpringLaw::rotation_vector, "rotation_vector"}}};
inline std::string_view name(SpringLaw law) { return name_in(kSpringLawNames, law); }

// A spring-damper on the relative rotation of a joint's two bodies. The
// damper moment is -C w_rel, w_rel the relative angular velocity in the
// child's frame.
struct JointSpring {
  Mat3 stiffness = Mat3::Zero();      // N m / rad, symmetric positive semi-definite, child frame
  Mat3 damping = Mat3::Zero();        // N m s / rad, symmetric positive semi-definite, child frame
  Quat reference = Quat::Identity();  // unloaded orientation of child relative to parent
  SpringLaw law = SpringLaw::quaternion;
};

struct JointSpec {
  std::string name;               // optional; defaults to "<parent>-<child>"
  std::string parent;             // a body name, or kBaseName
  std::string child;              // a body name
  Vec3 on_parent = Vec3::Zero();  // joint point from the parent's CoM, parent frame
                                  // (for the base joint: r0 is the point itself; ignored)
  Vec3 on_child = Vec3::Zero();   // joint point from the child's CoM, child frame
  // Chain links: the joint sits at the ends of cylinders and moves with their
  // lengths, on_child = (0, 0, +L_child / 2), on_parent = (0, 0, -L_parent / 2);
  // on_child / on_parent above are then unused.
  bool on_child_follows_length = false;
  bool on_parent_follows_length = false;
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
  std::vector<JointSpec> joints;  // one per body: joint a connects child a to its parent
  Vec3 gravity{0.0, 0.0, -9.81};  // m/s^2
  BaseMotionSpec base_motion = FixedBase{};
  std::vector<PointForce> forces;
  std::vector<BodyMoment> moments;
};

}  // namespace treedyn
