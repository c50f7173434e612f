// build_model: every validation error is a ModelError whose message names the
// offending body or joint and says what is wrong; valid models in any order
// are relabelled into the regular order; the section-3 constants (subtree
// masses, barycentres, b_i0, K_i) match a hand computation and the identities
// of docs/wittenburg.md on random trees.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <string>

#include "common/error.hpp"
#include "model/model.hpp"
#include "support/random_tree.hpp"

namespace treedyn {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

BodySpec body(const std::string& name, double mass = 1.0, const Mat3& inertia = 0.1 * Mat3::Identity()) {
  BodySpec b;
  b.name = name;
  b.mass = mass;
  b.inertia = inertia;
  return b;
}

JointSpec joint(const std::string& parent, const std::string& child, const std::string& name = "") {
  JointSpec j;
  j.name = name;
  j.parent = parent;
  j.child = child;
  j.on_parent = Vec3(0.3, 0.0, 0.0);
  j.on_child = Vec3(0.0, 0.0, 0.2);
  return j;
}

// A valid three-body chain: base -> root -> arm -> hand, joints named.
ModelSpec valid_chain() {
  ModelSpec s;
  s.bodies = {body("root"), body("arm"), body("hand")};
  s.joints = {joint(kBaseName, "root", "shoulder"), joint("root", "arm", "elbow"), joint("arm", "hand", "wrist")};
  return s;
}

// Runs build_model, expects a ModelError, returns its message ("" otherwise,
// which then fails the caller's EXPECTs with a readable message).
std::string model_error(const ModelSpec& spec) {
  try {
    build_model(spec);
  } catch (const ModelError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected ModelError, got another exception: " << e.what();
    return "";
  } catch (...) {
    ADD_FAILURE() << "expected ModelError, got a non-std exception";
    return "";
  }
  ADD_FAILURE() << "expected ModelError, build_model accepted the model";
  return "";
}

#define EXPECT_MESSAGE_HAS(message, part) \
  EXPECT_NE((message).find(part), std::string::npos) << "message: \"" << (message) << "\"\nlacks: \"" << (part) << "\""

// ---------------------------------------------------------------- topology

TEST(Validation, ValidChainBuilds) { EXPECT_NO_THROW(build_model(valid_chain())); }

TEST(Validation, CycleNamesABodyOfTheCycle) {
  ModelSpec s;
  s.bodies = {body("root"), body("ping"), body("pong")};
  s.joints = {joint(kBaseName, "root", "j0"), joint("pong", "ping", "j1"), joint("ping", "pong", "j2")};
  const std::string msg = model_error(s);
  EXPECT_TRUE(msg.find("'ping'") != std::string::npos || msg.find("'pong'") != std::string::npos) << msg;
  EXPECT_MESSAGE_HAS(msg, "cycle");
  EXPECT_EQ(msg.find("'root'"), std::string::npos) << "the valid root is not the culprit: " << msg;
}

TEST(Validation, UnreachableBodyWithoutJoint) {
  ModelSpec s = valid_chain();
  s.bodies.push_back(body("orphan"));
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "'orphan'");
  EXPECT_MESSAGE_HAS(msg, "unreachable");
  EXPECT_MESSAGE_HAS(msg, "no joint");
}

TEST(Validation, SelfParent) {
  ModelSpec s = valid_chain();
  s.joints[2] = joint("hand", "hand", "wrist");
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "'wrist'");
  EXPECT_MESSAGE_HAS(msg, "'hand'");
  EXPECT_MESSAGE_HAS(msg, "own parent");
}

TEST(Validation, SelfParentUnnamedJointIsLabelledByIndexAndBodies) {
  ModelSpec s = valid_chain();
  s.joints[2] = joint("hand", "hand");
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "joint 3");
  EXPECT_MESSAGE_HAS(msg, "'hand'");
  EXPECT_MESSAGE_HAS(msg, "own parent");
}

TEST(Validation, NoBodyOnTheBase) {
  // Two bodies, each the other's parent: every body has a joint, none hangs
  // from the base. There is no single offending body, so the message names the
  // missing base attachment.
  ModelSpec s;
  s.bodies = {body("a"), body("b")};
  s.joints = {joint("b", "a", "ab"), joint("a", "b", "ba")};
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "no body is attached");
  EXPECT_MESSAGE_HAS(msg, "'base'");
}

TEST(Validation, TwoBodiesOnTheBase) {
  ModelSpec s = valid_chain();
  s.bodies.push_back(body("second"));
  s.joints.push_back(joint(kBaseName, "second", "hip"));
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "'second'");
  EXPECT_MESSAGE_HAS(msg, "'root'");
  EXPECT_MESSAGE_HAS(msg, "second body on 'base'");
}

TEST(Validation, UnknownParentName) {
  ModelSpec s = valid_chain();
  s.joints[1].parent = "ghost";
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "'elbow'");
  EXPECT_MESSAGE_HAS(msg, "parent 'ghost'");
  EXPECT_MESSAGE_HAS(msg, "neither a body nor 'base'");
}

TEST(Validation, UnknownChildName) {
  ModelSpec s = valid_chain();
  s.joints[2].child = "ghost";
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "'wrist'");
  EXPECT_MESSAGE_HAS(msg, "child 'ghost'");
  EXPECT_MESSAGE_HAS(msg, "not a body of the model");
}

TEST(Validation, UnknownChildNameUnnamedJoint) {
  ModelSpec s = valid_chain();
  s.joints[2] = joint("arm", "ghost");
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "joint 3");
  EXPECT_MESSAGE_HAS(msg, "'ghost'");
  EXPECT_MESSAGE_HAS(msg, "not a body of the model");
}

TEST(Validation, TwoJointsToOneChild) {
  ModelSpec s = valid_chain();
  s.joints.push_back(joint("root", "hand", "extra"));
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "body 'hand'");
  EXPECT_MESSAGE_HAS(msg, "'wrist'");
  EXPECT_MESSAGE_HAS(msg, "'extra'");
  EXPECT_MESSAGE_HAS(msg, "two joints");
}

TEST(Validation, DuplicateBodyName) {
  ModelSpec s = valid_chain();
  s.bodies.push_back(body("arm"));
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "body 'arm'");
  EXPECT_MESSAGE_HAS(msg, "more than one body");
}

TEST(Validation, BodyNamedBase) {
  ModelSpec s = valid_chain();
  s.bodies[1].name = kBaseName;
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "body 2");
  EXPECT_MESSAGE_HAS(msg, "'base'");
  EXPECT_MESSAGE_HAS(msg, "reserved");
}

TEST(Validation, EmptyBodyName) {
  ModelSpec s = valid_chain();
  s.bodies[2].name = "";
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "body 3");
  EXPECT_MESSAGE_HAS(msg, "empty");
}

TEST(Validation, NoBodies) {
  const std::string msg = model_error(ModelSpec{});
  EXPECT_MESSAGE_HAS(msg, "no bodies");
}

// ------------------------------------------------------------------ bodies

void expect_bad_mass(double mass) {
  SCOPED_TRACE("mass " + std::to_string(mass));
  ModelSpec s = valid_chain();
  s.bodies[1].mass = mass;
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "body 'arm'");
  EXPECT_MESSAGE_HAS(msg, "mass");
  EXPECT_MESSAGE_HAS(msg, "positive and finite");
}

TEST(Validation, MassZero) { expect_bad_mass(0.0); }
TEST(Validation, MassNegative) { expect_bad_mass(-1.5); }
TEST(Validation, MassNaN) { expect_bad_mass(kNaN); }
TEST(Validation, MassInfinite) { expect_bad_mass(kInf); }
TEST(Validation, MassMinusInfinite) { expect_bad_mass(-kInf); }

std::string inertia_error(const Mat3& inertia) {
  ModelSpec s = valid_chain();
  s.bodies[2].inertia = inertia;
  return model_error(s);
}

TEST(Validation, InertiaNonSymmetric) {
  Mat3 J = Vec3(1.0, 1.2, 1.4).asDiagonal();
  J(0, 1) = 0.1;
  J(1, 0) = 0.2;
  const std::string msg = inertia_error(J);
  EXPECT_MESSAGE_HAS(msg, "body 'hand'");
  EXPECT_MESSAGE_HAS(msg, "not symmetric");
}

TEST(Validation, InertiaNotPositiveDefinite) {
  {
    const std::string msg = inertia_error(Vec3(1.0, 1.0, -0.5).asDiagonal());
    EXPECT_MESSAGE_HAS(msg, "body 'hand'");
    EXPECT_MESSAGE_HAS(msg, "not positive definite");
  }
  {  // Singular (a zero principal moment) is not positive definite either.
    const std::string msg = inertia_error(Vec3(1.0, 1.0, 0.0).asDiagonal());
    EXPECT_MESSAGE_HAS(msg, "body 'hand'");
    EXPECT_MESSAGE_HAS(msg, "not positive definite");
  }
  {  // Symmetric with positive diagonal, but indefinite (rotated frame).
    Mat3 J;
    J << 1.0, 2.0, 0.0,  //
        2.0, 1.0, 0.0,   //
        0.0, 0.0, 1.0;
    const std::string msg = inertia_error(J);
    EXPECT_MESSAGE_HAS(msg, "body 'hand'");
    EXPECT_MESSAGE_HAS(msg, "not positive definite");
  }
}

TEST(Validation, InertiaViolatesTriangleInequality) {
  {
    const std::string msg = inertia_error(Vec3(1.0, 1.0, 3.0).asDiagonal());
    EXPECT_MESSAGE_HAS(msg, "body 'hand'");
    EXPECT_MESSAGE_HAS(msg, "triangle inequality");
  }
  {  // Same moments in a rotated frame.
    const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, 3.0).normalized()).toRotationMatrix();
    const std::string msg = inertia_error(inertia_from_principal(Vec3(1.0, 3.0, 1.0), R));
    EXPECT_MESSAGE_HAS(msg, "body 'hand'");
    EXPECT_MESSAGE_HAS(msg, "triangle inequality");
  }
  // The limiting case A + B = C (a thin plate / rod-like body) is allowed.
  EXPECT_NO_THROW(build_model([] {
    ModelSpec s = valid_chain();
    s.bodies[2].inertia = Vec3(1.0, 2.0, 3.0).asDiagonal();
    return s;
  }()));
}

TEST(Validation, InertiaNaN) {
  Mat3 J = 0.1 * Mat3::Identity();
  J(2, 2) = kNaN;
  const std::string msg = inertia_error(J);
  EXPECT_MESSAGE_HAS(msg, "body 'hand'");
  EXPECT_MESSAGE_HAS(msg, "NaN");
}

// ------------------------------------------------------------------ joints

TEST(Validation, NaNJointPointOnChild) {
  ModelSpec s = valid_chain();
  s.joints[1].on_child = Vec3(0.0, kNaN, 0.0);
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "joint 'elbow'");
  EXPECT_MESSAGE_HAS(msg, "on_child");
  EXPECT_MESSAGE_HAS(msg, "finite");
}

TEST(Validation, NaNJointPointOnParent) {
  ModelSpec s = valid_chain();
  s.joints[2].on_parent = Vec3(kNaN, 0.0, 0.0);
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "joint 'wrist'");
  EXPECT_MESSAGE_HAS(msg, "on_parent");
  EXPECT_MESSAGE_HAS(msg, "finite");
}

TEST(Validation, InfiniteJointPointOnRootChild) {
  ModelSpec s = valid_chain();
  s.joints[0].on_child = Vec3(0.0, 0.0, kInf);
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "joint 'shoulder'");
  EXPECT_MESSAGE_HAS(msg, "on_child");
}

TEST(Validation, UnnamedJointIsNamedParentDashChild) {
  ModelSpec s = valid_chain();
  s.joints[1].name = "";
  s.joints[1].on_child = Vec3(0.0, kNaN, 0.0);
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "joint 'root-arm'");
}

TEST(Validation, NaNGravity) {
  ModelSpec s = valid_chain();
  s.gravity = Vec3(0.0, 0.0, kNaN);
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "gravity");
  EXPECT_MESSAGE_HAS(msg, "finite");
}

TEST(Validation, NegativeDefiniteStiffness) {
  ModelSpec s = valid_chain();
  s.joints[1].spring.stiffness = -2.0 * Mat3::Identity();
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "joint 'elbow'");
  EXPECT_MESSAGE_HAS(msg, "stiffness");
  EXPECT_MESSAGE_HAS(msg, "negative eigenvalue");
}

TEST(Validation, IndefiniteDamping) {
  ModelSpec s = valid_chain();
  s.joints[2].spring.damping = Vec3(1.0, 1.0, -0.1).asDiagonal();
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "joint 'wrist'");
  EXPECT_MESSAGE_HAS(msg, "damping");
  EXPECT_MESSAGE_HAS(msg, "negative eigenvalue");
}

TEST(Validation, ZeroReferenceQuaternion) {
  ModelSpec s = valid_chain();
  s.joints[0].spring.reference = Quat(0.0, 0.0, 0.0, 0.0);
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "joint 'shoulder'");
  EXPECT_MESSAGE_HAS(msg, "reference");
}

TEST(Validation, PointForceOnUnknownBody) {
  ModelSpec s = valid_chain();
  PointForce f;
  f.body = "arm";
  s.forces.push_back(f);
  f.body = "ghost";
  s.forces.push_back(f);
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "force 2");
  EXPECT_MESSAGE_HAS(msg, "'ghost'");
  EXPECT_MESSAGE_HAS(msg, "not a body of the model");
}

TEST(Validation, PointForceWithNaNPoint) {
  ModelSpec s = valid_chain();
  PointForce f;
  f.body = "arm";
  f.point = Vec3(kNaN, 0.0, 0.0);
  s.forces.push_back(f);
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "force 1");
  EXPECT_MESSAGE_HAS(msg, "point");
  EXPECT_MESSAGE_HAS(msg, "finite");
}

TEST(Validation, MomentOnUnknownBody) {
  ModelSpec s = valid_chain();
  BodyMoment m;
  m.body = "ghost";
  s.moments.push_back(m);
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "moment 1");
  EXPECT_MESSAGE_HAS(msg, "'ghost'");
}

TEST(Validation, InvalidBaseMotionIsAModelError) {
  ModelSpec s = valid_chain();
  TabulatedBase tab;
  tab.times = {0.0, 1.0, 1.0};
  tab.positions = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  s.base_motion = tab;
  const std::string msg = model_error(s);
  EXPECT_MESSAGE_HAS(msg, "tabulated");
  EXPECT_MESSAGE_HAS(msg, "strictly increasing");
}

// -------------------------------------------------------------- relabelling

void expect_regular(const Model& m, const ModelSpec& spec) {
  const int n = m.n;
  ASSERT_EQ(n, static_cast<int>(spec.bodies.size()));
  ASSERT_EQ(static_cast<int>(m.tree().parent.size()), n);
  ASSERT_EQ(static_cast<int>(m.tree().user_index.size()), n);
  ASSERT_EQ(static_cast<int>(m.tree().regular_index.size()), n);
  ASSERT_EQ(static_cast<int>(m.tree().body_name.size()), n);
  EXPECT_EQ(m.tree().parent[0], kBase);
  for (int i = 1; i < n; ++i) {
    EXPECT_GE(m.tree().parent[i], 0) << "only body 0 hangs from the base";
    EXPECT_LT(m.tree().parent[i], i) << "body " << i;
  }
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(m.tree().regular_index[m.tree().user_index[i]], i);
    EXPECT_EQ(m.tree().user_index[m.tree().regular_index[i]], i);
    EXPECT_EQ(m.tree().body_name[i], spec.bodies[m.tree().user_index[i]].name);
    EXPECT_EQ(m.mass[i], spec.bodies[m.tree().user_index[i]].mass);
    EXPECT_EQ(m.tree().depth[i], m.tree().parent[i] == kBase ? 1 : m.tree().depth[m.tree().parent[i]] + 1);
    EXPECT_TRUE(std::is_sorted(m.tree().children[i].begin(), m.tree().children[i].end()));
    for (int k : m.tree().children[i]) EXPECT_EQ(m.tree().parent[k], i);
  }
  std::vector<int> sorted = m.tree().user_index;
  std::sort(sorted.begin(), sorted.end());
  std::vector<int> identity(n);
  std::iota(identity.begin(), identity.end(), 0);
  EXPECT_EQ(sorted, identity) << "user_index is a permutation";

  // The joint of regular body i names body i as its child and p(i) (or the
  // base) as its parent.
  for (const JointSpec& j : spec.joints) {
    const auto child = std::find(m.tree().body_name.begin(), m.tree().body_name.end(), j.child);
    ASSERT_NE(child, m.tree().body_name.end());
    const int i = static_cast<int>(child - m.tree().body_name.begin());
    if (j.parent == kBaseName) {
      EXPECT_EQ(m.tree().parent[i], kBase);
    } else {
      ASSERT_NE(m.tree().parent[i], kBase);
      EXPECT_EQ(m.tree().body_name[m.tree().parent[i]], j.parent);
    }
    EXPECT_EQ(m.com_to_inboard_joint[i], j.on_child);
    if (m.tree().parent[i] != kBase) {
      EXPECT_EQ(m.parent_com_to_joint[i], j.on_parent);
    }
  }
  // Preorder: every subtree is a contiguous index range.
  for (int i = 0; i < n; ++i) {
    int last = i;
    for (int j = i + 1; j < n && (m.tree().is_ancestor(i, j)); ++j) last = j;
    for (int j = last + 1; j < n; ++j) EXPECT_FALSE(m.tree().is_ancestor(i, j)) << i << " " << j;
  }
}

TEST(Relabel, HandWrittenShuffledOrder) {
  // base -> c -> {a, d}, d -> b; listed in an order where children come first.
  ModelSpec s;
  s.bodies = {body("b", 1.0), body("a", 2.0), body("d", 3.0), body("c", 4.0)};
  s.joints = {joint("d", "b"), joint("c", "a"), joint(kBaseName, "c"), joint("c", "d")};
  PointForce f;
  f.body = "b";
  f.force = Vec3(1.0, 2.0, 3.0);
  s.forces.push_back(f);
  BodyMoment mo;
  mo.body = "a";
  mo.moment = Vec3(0.0, 0.0, 5.0);
  s.moments.push_back(mo);
  const Model m = build_model(s);
  expect_regular(m, s);
  EXPECT_EQ(m.tree().body_name[0], "c");
  EXPECT_EQ(m.tree().user_index[0], 3);
  EXPECT_EQ(m.tree().regular_index[3], 0);
  EXPECT_DOUBLE_EQ(m.total_mass, 10.0);
  const int b = m.tree().regular_index[0];
  const int a = m.tree().regular_index[1];
  const int d = m.tree().regular_index[2];
  EXPECT_EQ(m.tree().body_name[b], "b");
  EXPECT_EQ(m.tree().parent[b], d);
  EXPECT_EQ(m.tree().parent[d], 0);
  EXPECT_EQ(m.tree().parent[a], 0);
  EXPECT_DOUBLE_EQ(m.subtree_mass[d], 4.0);
  ASSERT_EQ(m.point_forces[b].size(), 1u);
  EXPECT_EQ(m.point_forces[b][0].force, Vec3(1.0, 2.0, 3.0));
  EXPECT_TRUE(m.has_point_forces);
  EXPECT_EQ(m.applied_moment[a], Vec3(0.0, 0.0, 5.0));
  EXPECT_EQ(m.tree().joint_name[b], "d-b");
}

TEST(Relabel, RandomShuffledTrees) {
  std::mt19937_64 rng(777);
  for (int n : {1, 2, 3, 5, 8, 13, 30}) {
    for (bool chain : {false, true}) {
      SCOPED_TRACE("n " + std::to_string(n) + (chain ? " chain" : " tree"));
      testing::RandomTreeOptions options;
      options.bodies = n;
      options.chain = chain;
      ModelSpec spec = testing::random_tree(rng, options);
      // Also shuffle the joints independently of the bodies.
      std::shuffle(spec.joints.begin(), spec.joints.end(), rng);
      const Model m = build_model(spec);
      expect_regular(m, spec);
    }
  }
}

// --------------------------------------------------- section-3 constants

Mat3 point_mass_inertia(double mass, const Vec3& d) {
  return mass * (d.squaredNorm() * Mat3::Identity() - d * d.transpose());
}

// Y tree: base -> R -> {A, B}, nearly point masses (J = 1e-4 E, included in K).
TEST(Constants, HandComputedYTree) {
  const Mat3 J = 1e-4 * Mat3::Identity();
  ModelSpec s;
  s.bodies = {body("B", 3.0, J), body("A", 1.0, J), body("R", 2.0, J)};  // not regular order
  JointSpec jr = joint(kBaseName, "R", "jR");
  jr.on_child = Vec3(0.0, 0.0, 1.0);
  JointSpec ja = joint("R", "A", "jA");
  ja.on_parent = Vec3(1.0, 0.0, 0.0);
  ja.on_child = Vec3(0.0, 0.0, 0.5);
  JointSpec jb = joint("R", "B", "jB");
  jb.on_parent = Vec3(-1.0, 0.0, 0.0);
  jb.on_child = Vec3(0.0, 0.5, 0.0);
  s.joints = {ja, jb, jr};
  const Model m = build_model(s);
  const int R = m.tree().regular_index[2], A = m.tree().regular_index[1], B = m.tree().regular_index[0];
  ASSERT_EQ(R, 0);
  const double tol = 1e-14;

  // mu and M.
  EXPECT_DOUBLE_EQ(m.total_mass, 6.0);
  EXPECT_DOUBLE_EQ(m.subtree_mass[R], 6.0);
  EXPECT_DOUBLE_EQ(m.subtree_mass[A], 1.0);
  EXPECT_DOUBLE_EQ(m.subtree_mass[B], 3.0);

  // beta_R = (0 * c_RR + 1 * (1,0,0) + 3 * (-1,0,0)) / 6 = (-1/3, 0, 0)
  // beta_A = (5 * (0,0,1/2)) / 6 = (0, 0, 5/12), beta_B = (3 * (0,1/2,0)) / 6 = (0, 1/4, 0)
  EXPECT_TRUE(m.barycentre[R].isApprox(Vec3(-1.0 / 3.0, 0.0, 0.0), tol)) << m.barycentre[R].transpose();
  EXPECT_TRUE(m.barycentre[A].isApprox(Vec3(0.0, 0.0, 5.0 / 12.0), tol)) << m.barycentre[A].transpose();
  EXPECT_TRUE(m.barycentre[B].isApprox(Vec3(0.0, 0.25, 0.0), tol)) << m.barycentre[B].transpose();

  // b_i0 = c_ii - beta_i.
  EXPECT_TRUE(m.barycentre_to_inboard[R].isApprox(Vec3(1.0 / 3.0, 0.0, 1.0), tol));
  EXPECT_TRUE(m.barycentre_to_inboard[A].isApprox(Vec3(0.0, 0.0, 1.0 / 12.0), tol));
  EXPECT_TRUE(m.barycentre_to_inboard[B].isApprox(Vec3(0.0, 0.25, 0.0), tol));

  // d_{R j} for j in sub(k): c_RR - c_Rk.
  EXPECT_TRUE(m.branch_d[A].isApprox(Vec3(-1.0, 0.0, 1.0), tol));
  EXPECT_TRUE(m.branch_d[B].isApprox(Vec3(1.0, 0.0, 1.0), tol));

  // K_R = J + 2 pm(0,0,1) + 1 pm(-1,0,1) + 3 pm(1,0,1)
  //     = J + diag(2,2,0) + [[1,0,1],[0,2,0],[1,0,1]] + [[3,0,-3],[0,6,0],[-3,0,3]]
  Mat3 KR;
  KR << 6.0, 0.0, -2.0,  //
      0.0, 10.0, 0.0,    //
      -2.0, 0.0, 4.0;
  KR += J;
  const Mat3 KA = J + Mat3(Vec3(0.25, 0.25, 0.0).asDiagonal());  // 1 * pm(0,0,1/2)
  const Mat3 KB = J + Mat3(Vec3(0.75, 0.0, 0.75).asDiagonal());  // 3 * pm(0,1/2,0)
  EXPECT_TRUE(m.augmented_inertia[R].isApprox(KR, tol)) << m.augmented_inertia[R];
  EXPECT_TRUE(m.augmented_inertia[A].isApprox(KA, tol)) << m.augmented_inertia[A];
  EXPECT_TRUE(m.augmented_inertia[B].isApprox(KB, tol)) << m.augmented_inertia[B];

  // sum_j m_j b_Rj = 0 with b_RR = -beta_R, b_RA = c_RA - beta_R, b_RB = c_RB - beta_R.
  const Vec3 sum = 2.0 * (-m.barycentre[R]) + 1.0 * (Vec3(1.0, 0.0, 0.0) - m.barycentre[R]) +
                   3.0 * (Vec3(-1.0, 0.0, 0.0) - m.barycentre[R]);
  EXPECT_LT(sum.norm(), 1e-14);
}

// The b- and d-vectors of docs/wittenburg.md, built from the model's fields.
Vec3 b_vector(const Model& m, int i, int j) {
  const Vec3& beta = m.barycentre[i];
  if (i == j) return -beta;
  for (int k : m.tree().children[i])
    if (k == j || m.tree().is_ancestor(k, j)) return m.parent_com_to_joint[k] - beta;
  return m.com_to_inboard_joint[i] - beta;  // j not in sub(i): b_i0
}

Vec3 b_inboard(const Model& m, int i) { return m.com_to_inboard_joint[i] - m.barycentre[i]; }

Vec3 d_vector(const Model& m, int i, int j) {
  if (i == j) return m.com_to_inboard_joint[i];
  for (int k : m.tree().children[i])
    if (k == j || m.tree().is_ancestor(k, j)) return m.com_to_inboard_joint[i] - m.parent_com_to_joint[k];
  return Vec3::Zero();
}

TEST(Constants, RandomTreesSatisfyPageIdentities) {
  std::mt19937_64 rng(4242);
  for (int trial = 0; trial < 20; ++trial) {
    testing::RandomTreeOptions options;
    options.bodies = 1 + trial % 12;
    options.chain = trial % 5 == 0;
    const ModelSpec spec = testing::random_tree(rng, options);
    const Model m = build_model(spec);
    SCOPED_TRACE("trial " + std::to_string(trial) + ", n " + std::to_string(m.n));
    const double M = std::accumulate(m.mass.begin(), m.mass.end(), 0.0);
    EXPECT_NEAR(m.total_mass, M, 1e-13 * M);
    for (int i = 0; i < m.n; ++i) {
      // mu_i by membership.
      double mu = 0.0;
      for (int j = 0; j < m.n; ++j)
        if (j == i || m.tree().is_ancestor(i, j)) mu += m.mass[j];
      EXPECT_NEAR(m.subtree_mass[i], mu, 1e-13 * M);

      Vec3 sum_b = Vec3::Zero(), sum_d = Vec3::Zero();
      Mat3 K = m.inertia[i];
      double scale = 0.0;
      for (int j = 0; j < m.n; ++j) {
        const Vec3 b = b_vector(m, i, j);
        const Vec3 d = d_vector(m, i, j);
        sum_b += m.mass[j] * b;
        sum_d += m.mass[j] * d;
        K += point_mass_inertia(m.mass[j], d);
        scale += m.mass[j] * b.norm();
        // (40): d_ij = b_i0 - b_ij.
        EXPECT_LT((d - (b_inboard(m, i) - b)).norm(), 1e-13) << "i " << i << " j " << j;
      }
      EXPECT_LT(sum_b.norm(), 1e-13 * std::max(scale, 1.0)) << "sum_j m_j b_ij, i " << i;
      EXPECT_LT((sum_d - M * m.barycentre_to_inboard[i]).norm(), 1e-13 * std::max(scale, 1.0))
          << "sum_j m_j d_ij = M b_i0, i " << i;
      EXPECT_LT((m.barycentre_to_inboard[i] - (m.com_to_inboard_joint[i] - m.barycentre[i])).norm(), 1e-15);
      EXPECT_TRUE(m.augmented_inertia[i].isApprox(K, 1e-12)) << "K_" << i << "\n"
                                                             << m.augmented_inertia[i] << "\nvs\n"
                                                             << K;
      for (int k : m.tree().children[i]) EXPECT_LT((m.branch_d[k] - d_vector(m, i, k)).norm(), 1e-15);
    }
  }
}

}  // namespace
}  // namespace treedyn
