// The parameter vector (model/parameters.*, define_model.cpp,
// derive_model.cpp): names, units and layout; derive_model() on any vector
// gives the physics the names promise, checked against formulas written out
// here; storage is reused without leaking one sample into the next; and
// unphysical values are refused with a ModelError naming the body.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "model/definition.hpp"

namespace treedyn {
namespace {

constexpr double kPi = std::numbers::pi;

// A box given by mass on the base, a cylinder given by density below it,
// an explicit-inertia body, and two chain-style links whose joints follow
// their lengths; a harmonic base, a force and a moment.
ModelSpec mixed_spec() {
  ModelSpec s;
  BodySpec box;
  box.name = "box";
  box.solid = Solid::box;
  box.size = Vec3(0.2, 0.3, 0.4);
  box.mass = 3.0;
  BodySpec cyl;
  cyl.name = "cyl";
  cyl.solid = Solid::cylinder;
  cyl.radius = 0.05;
  cyl.length = 0.6;
  cyl.density = 2700.0;
  BodySpec arm;
  arm.name = "arm";
  arm.mass = 1.5;
  arm.inertia << 0.2, 0.01, 0.0, 0.01, 0.3, 0.0, 0.0, 0.0, 0.25;
  BodySpec l1, l2;
  for (BodySpec* l : {&l1, &l2}) {
    l->solid = Solid::cylinder;
    l->radius = 0.01;
    l->mass = 0.4;
  }
  l1.name = "l1";
  l1.length = 0.5;
  l2.name = "l2";
  l2.length = 0.7;
  s.bodies = {box, cyl, arm, l1, l2};
  auto joint = [](std::string parent, std::string child, Vec3 on_parent, Vec3 on_child) {
    JointSpec j;
    j.parent = std::move(parent);
    j.child = std::move(child);
    j.on_parent = on_parent;
    j.on_child = on_child;
    return j;
  };
  s.joints = {joint(kBaseName, "box", Vec3::Zero(), Vec3(0, 0, 0.2)),
              joint("box", "cyl", Vec3(0, 0, -0.2), Vec3(0, 0, 0.3)),
              joint("cyl", "arm", Vec3(0.05, 0, -0.3), Vec3(0, 0.1, 0)),
              joint("box", "l1", Vec3(0.1, 0, 0), Vec3::Zero()), joint("l1", "l2", Vec3::Zero(), Vec3::Zero())};
  s.joints[3].on_child_follows_length = true;
  s.joints[4].on_child_follows_length = true;
  s.joints[4].on_parent_follows_length = true;
  s.joints[2].spring.stiffness = 2.0 * Mat3::Identity();
  HarmonicBase h;
  h.axes[2].push_back({0.01, 5.0, 0.3});
  s.base_motion = h;
  s.forces.push_back({"arm", Vec3(0.1, 0, 0), Vec3(0, 1, 0)});
  s.moments.push_back({"cyl", Vec3(0, 0, 0.5)});
  return s;
}

int regular(const ModelDefinition& d, const std::string& name) {
  return d.topology->regular_index[d.topology->find_user_body(name)];
}

TEST(Parameters, NamesUnitsAndLayoutFollowTheDescription) {
  const ModelDefinition d = define_model(mixed_spec());
  std::vector<std::string> names, units;
  for (const Parameter& p : d.parameters.parameters()) {
    names.push_back(p.name);
    units.push_back(p.unit);
    EXPECT_FALSE(p.enters.empty()) << p.name;
  }
  // clang-format off
  const std::vector<std::string> expected = {
      "body.box.mass", "body.box.size", "body.box.inertia_scale", "body.box.joint_on_child",
      "joint.box.stiffness", "joint.box.damping",
      "body.cyl.density", "body.cyl.radius", "body.cyl.length", "body.cyl.inertia_scale",
      "body.cyl.joint_on_child", "body.cyl.joint_on_parent", "joint.cyl.stiffness", "joint.cyl.damping",
      "body.arm.mass", "body.arm.inertia", "body.arm.inertia_scale", "body.arm.joint_on_child",
      "body.arm.joint_on_parent", "joint.arm.stiffness", "joint.arm.damping",
      "body.l1.mass", "body.l1.radius", "body.l1.length", "body.l1.inertia_scale",
      "body.l1.joint_on_parent", "joint.l1.stiffness", "joint.l1.damping",
      "body.l2.mass", "body.l2.radius", "body.l2.length", "body.l2.inertia_scale",
      "joint.l2.stiffness", "joint.l2.damping",
      "gravity", "base.offset", "base.z[1].amplitude", "base.z[1].frequency", "base.z[1].phase",
      "force[1].point", "force[1].force", "moment[1].moment"};
  // clang-format on
  EXPECT_EQ(names, expected);
  EXPECT_EQ(d.parameters.find("body.cyl.density")->unit, "kg/m^3");
  EXPECT_EQ(d.parameters.find("joint.arm.stiffness")->unit, "N m/rad");
  EXPECT_EQ(d.parameters.find("base.z[1].phase")->unit, "rad");
  EXPECT_EQ(d.parameters.find("body.arm.inertia")->shape, ParameterShape::matrix3);
  // Entries: contiguous, in order, each named.
  const Parameter& size = *d.parameters.find("body.box.size");
  EXPECT_EQ(d.parameters.entry_name(size.offset + 2), "body.box.size.z");
  EXPECT_EQ(d.parameters.nominal()[size.offset + 1], 0.3);
  const Parameter& inertia = *d.parameters.find("body.arm.inertia");
  EXPECT_EQ(d.parameters.entry_name(inertia.offset + 1), "body.arm.inertia.xy");
  EXPECT_EQ(&d.parameters.owner(inertia.offset + 8), &inertia);
  EXPECT_EQ(d.parameters.entry_name(static_cast<int>(d.parameters.size()) - 1), "moment[1].moment.z");
  EXPECT_THROW(d.parameters.entry_name(static_cast<int>(d.parameters.size())), std::out_of_range);
}

// Solids are homogeneous whatever the vector says: mass from the density and
// the volume when the density is given, the inertia from the textbook
// formulas (written out here) for the vector's mass and dimensions. To 1e-15
// relative (a few roundings).
TEST(Parameters, SolidsStayHomogeneous) {
  const ModelDefinition d = define_model(mixed_spec());
  std::vector<double> p(d.parameters.nominal().begin(), d.parameters.nominal().end());
  auto set = [&](const std::string& name, double v, int c = 0) { p[d.parameters.find(name)->offset + c] = v; };
  set("body.box.mass", 4.0);
  set("body.box.size", 0.5, 2);
  set("body.cyl.density", 8000.0);
  set("body.cyl.length", 0.9);
  set("body.l2.length", 1.1);
  Model m;
  derive_model(d, p, m);
  auto near = [](double a, double b) { return std::abs(a - b) <= 1e-15 * std::abs(b); };

  const int box = regular(d, "box");
  EXPECT_EQ(m.mass[box], 4.0);
  const double x = 0.2, y = 0.3, z = 0.5;
  EXPECT_TRUE(near(m.inertia[box](0, 0), 4.0 * (y * y + z * z) / 12.0));
  EXPECT_TRUE(near(m.inertia[box](1, 1), 4.0 * (x * x + z * z) / 12.0));
  EXPECT_TRUE(near(m.inertia[box](2, 2), 4.0 * (x * x + y * y) / 12.0));

  const int cyl = regular(d, "cyl");
  const double r = 0.05, L = 0.9, mass = 8000.0 * kPi * r * r * L;
  EXPECT_TRUE(near(m.mass[cyl], mass)) << m.mass[cyl] << " vs " << mass;
  EXPECT_TRUE(near(m.inertia[cyl](0, 0), mass * (3 * r * r + L * L) / 12.0));
  EXPECT_TRUE(near(m.inertia[cyl](2, 2), mass * r * r / 2.0));
  EXPECT_EQ(m.inertia[cyl](0, 1), 0.0);
  // Its joint point was given explicitly: it stays where it was written.
  EXPECT_EQ(m.com_to_inboard_joint[cyl], Vec3(0, 0, 0.3));

  // A link whose joints follow its length: both of its ends move.
  const int l2 = regular(d, "l2");
  EXPECT_EQ(m.mass[l2], 0.4);  // given by mass: the mass stays
  EXPECT_EQ(m.com_to_inboard_joint[l2], Vec3(0, 0, 0.55));
  EXPECT_EQ(m.parent_com_to_joint[l2], Vec3(0, 0, -0.25));  // on l1, of l1's length 0.5
  EXPECT_EQ(m.com_to_inboard_joint[regular(d, "l1")], Vec3(0, 0, 0.25));
}

// An explicit inertia is what was written: a new mass changes the mass only.
TEST(Parameters, ExplicitInertiaMassChangesTheMassOnly) {
  const ModelDefinition d = define_model(mixed_spec());
  std::vector<double> p(d.parameters.nominal().begin(), d.parameters.nominal().end());
  Model nominal, heavier;
  derive_model(d, p, nominal);
  p[d.parameters.find("body.arm.mass")->offset] = 3.0;
  derive_model(d, p, heavier);
  const int arm = regular(d, "arm");
  EXPECT_EQ(heavier.mass[arm], 3.0);
  EXPECT_TRUE(heavier.inertia[arm] == nominal.inertia[arm]);
  EXPECT_NE(heavier.total_mass, nominal.total_mass);
  // inertia_scale multiplies it.
  p[d.parameters.find("body.arm.inertia_scale")->offset] = 2.0;
  derive_model(d, p, heavier);
  EXPECT_TRUE(heavier.inertia[arm].isApprox(2.0 * nominal.inertia[arm], 1e-15));
}

// One Model reused for several vectors is the same as a fresh one for each:
// nothing of an earlier vector survives (loads, springs, base motion).
TEST(Parameters, ReusedStorageKeepsNothingOfTheLastVector) {
  const ModelDefinition d = define_model(mixed_spec());
  std::vector<double> a(d.parameters.nominal().begin(), d.parameters.nominal().end()), b = a;
  b[d.parameters.find("force[1].force")->offset + 1] = 7.0;
  // Entries xy and yx, the second 1e-12 off: symmetric within the allowed 1e-9.
  b[d.parameters.find("joint.arm.stiffness")->offset + 1] = 1.0;
  b[d.parameters.find("joint.arm.stiffness")->offset + 3] = 1.0 + 1e-12;
  b[d.parameters.find("base.z[1].frequency")->offset] = 1.0;
  b[d.parameters.find("moment[1].moment")->offset + 2] = -2.0;
  Model reused, fresh_a, fresh_b;
  derive_model(d, b, reused);
  derive_model(d, a, reused);
  derive_model(d, a, fresh_a);
  derive_model(d, b, fresh_b);
  const int arm = regular(d, "arm"), cyl = regular(d, "cyl");
  ASSERT_EQ(reused.point_forces[arm].size(), 1u);
  EXPECT_EQ(reused.point_forces[arm][0].force, fresh_a.point_forces[arm][0].force);
  EXPECT_EQ(reused.applied_moment[cyl], fresh_a.applied_moment[cyl]);
  EXPECT_TRUE(reused.spring[arm].stiffness == fresh_a.spring[arm].stiffness);
  EXPECT_EQ(reused.base_motion.at(0.1).position, fresh_a.base_motion.at(0.1).position);
  EXPECT_NE(fresh_b.base_motion.at(0.1).position, fresh_a.base_motion.at(0.1).position);
  for (int i = 0; i < reused.n; ++i) EXPECT_TRUE(reused.augmented_inertia[i] == fresh_a.augmented_inertia[i]);
  // The entries land where they are named, and the matrix is symmetrised.
  const double mean = 0.5 * (1.0 + (1.0 + 1e-12));
  EXPECT_EQ(fresh_b.spring[arm].stiffness(0, 1), mean);
  EXPECT_EQ(fresh_b.spring[arm].stiffness(1, 0), mean);
  EXPECT_EQ(fresh_b.spring[arm].stiffness(0, 2), 0.0);
}

std::string refusal(const ModelDefinition& d, const std::string& name, double value, int c = 0) {
  std::vector<double> p(d.parameters.nominal().begin(), d.parameters.nominal().end());
  p[d.parameters.find(name)->offset + c] = value;
  Model m;
  try {
    derive_model(d, p, m);
  } catch (const ModelError& e) {
    return std::string(e.what()) + " [" + e.subject() + "]";
  }
  return "accepted";
}

// The physical checks run on the vector's values and name the body.
TEST(Parameters, UnphysicalValuesAreRefusedNamingTheBody) {
  const ModelDefinition d = define_model(mixed_spec());
  const std::vector<std::array<std::string, 3>> cases = {
      {"body.box.mass", "-1", "body 'box': mass -1 kg is not allowed"},
      {"body.cyl.density", "0", "body 'cyl': density 0 kg/m^3 is not allowed"},
      {"body.cyl.length", "-0.1", "body 'cyl': length -0.1 m is not allowed"},
      {"body.box.size", "0", "body 'box': size 0 m is not allowed"},
      {"body.arm.inertia_scale", "0", "body 'arm': inertia_scale 0 is not allowed"},
      {"body.arm.mass", "nan", "body 'arm': mass nan kg is not allowed"},
      {"joint.arm.stiffness", "-3", "stiffness has a negative eigenvalue"},
      {"body.arm.joint_on_child", "inf", "on_child"},
      {"base.z[1].frequency", "-1", "frequency must be finite and >= 0 Hz"},
  };
  for (const auto& [name, value, says] : cases) {
    const std::string message = refusal(d, name, std::stod(value));
    EXPECT_NE(message.find(says), std::string::npos) << name << " = " << value << ": " << message;
  }
  // The triangle inequality on a perturbed explicit inertia entry.
  EXPECT_NE(refusal(d, "body.arm.inertia", 5.0, 0).find("triangle inequality"), std::string::npos);
  // And the subject is the body, so the reader can point at its table.
  EXPECT_NE(refusal(d, "body.cyl.radius", -1.0).find("[cyl]"), std::string::npos);
}

}  // namespace
}  // namespace treedyn
