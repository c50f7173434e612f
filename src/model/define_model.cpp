// define_model: the tree, the names, and the parameter layout. Parameters are
// laid out in the description's order: per body (job order) its mass or
// density, dimensions or inertia, inertia scale, joint points and joint
// spring; then gravity, the base motion, the forces and the moments.
#include <array>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "common/error.hpp"
#include "model/definition.hpp"

namespace treedyn {
namespace {

using Shape = ParameterShape;

std::array<double, 3> entries(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
std::array<double, 9> entries(const Mat3& m) {  // row-major
  return {m(0, 0), m(0, 1), m(0, 2), m(1, 0), m(1, 1), m(1, 2), m(2, 0), m(2, 1), m(2, 2)};
}
std::array<double, 1> entries(double x) { return {x}; }

template <class T>
int add(ParameterTable& table, std::string name, std::string unit, Shape shape, std::string enters, const T& nominal,
        ValidRange valid = ValidRange::any()) {
  const auto values = entries(nominal);
  return table.add(std::move(name), std::move(unit), shape, std::move(enters), values, valid);
}

std::string quoted(const std::string& s) { return "'" + s + "'"; }

// What follows when the mass or a dimension of a solid changes.
std::string solid_note(const BodySpec& b) {
  return "homogeneous " + std::string(name_in(kSolidNames, b.solid)) + ": its inertia follows" +
         (b.density ? ", and its mass (density x volume)" : "; its mass stays");
}

// `ends_follow`: a joint sits at an end of this cylinder and moves with its length.
void add_body_parameters(ParameterTable& table, const BodySpec& b, bool ends_follow, BodyForm& form) {
  const std::string prefix = "body." + b.name + ".";
  const std::string who = quoted(b.name);
  form.solid = b.solid;
  if (b.solid == Solid::none) {
    form.mass = add(table, prefix + "mass", "kg", Shape::scalar,
                    "mass of " + who + " only: its inertia is given explicitly and stays as written", b.mass,
                    ValidRange::positive());
    form.inertia = add(table, prefix + "inertia", "kg m^2", Shape::matrix3,
                       "central inertia tensor of " + who + ", body frame (symmetrised when used)", b.inertia,
                       ValidRange::positive());
  } else {
    const std::string solid(name_in(kSolidNames, b.solid));
    if (b.density)
      form.density =
          add(table, prefix + "density", "kg/m^3", Shape::scalar,
              "density of the homogeneous " + solid + " " + who + ": its mass (density x volume) and inertia follow",
              *b.density, ValidRange::positive());
    else
      form.mass = add(table, prefix + "mass", "kg", Shape::scalar,
                      "mass of the homogeneous " + solid + " " + who + ": its inertia follows (dimensions stay)",
                      b.mass, ValidRange::positive());
    if (b.solid == Solid::box)
      form.size = add(table, prefix + "size", "m", Shape::vector3,
                      "edges of the box " + who + " along its body x, y, z (" + solid_note(b) + ")", b.size,
                      ValidRange::positive());
    else
      form.radius =
          add(table, prefix + "radius", "m", Shape::scalar,
              "radius of the " + solid + " " + who + " (" + solid_note(b) + ")", b.radius, ValidRange::positive());
    if (b.solid == Solid::cylinder)
      form.length = add(table, prefix + "length", "m", Shape::scalar,
                        "length of the cylinder " + who + " along its body z (" + solid_note(b) + ")" +
                            (ends_follow ? "; the joints at its ends (0, 0, +-L/2) move with it" : ""),
                        b.length, ValidRange::positive());
  }
  form.inertia_scale = add(table, prefix + "inertia_scale", "1", Shape::scalar,
                           "multiplies the inertia tensor of " + who + " (1: as given)", 1.0, ValidRange::positive());
}

void add_joint_parameters(ParameterTable& table, const std::string& child_name, const std::string& joint_name,
                          const JointSpec& j, bool on_base, JointForm& form) {
  const std::string prefix = "body." + child_name + ".";
  const std::string who = quoted(child_name);
  if (!j.on_child_follows_length)
    form.on_child = add(
        table, prefix + "joint_on_child", "m", Shape::vector3,
        "the joint point of " + who + " (its joint to its parent), from its CoM, " + "in its body frame", j.on_child);
  if (!on_base && !j.on_parent_follows_length)
    form.on_parent = add(table, prefix + "joint_on_parent", "m", Shape::vector3,
                         "the point of the joint of " + who + " on its parent " + quoted(j.parent) +
                             ", from the parent's CoM, in the parent's body frame",
                         j.on_parent);
  const std::string joint =
      "joint " + quoted(joint_name) + " (" + std::string(name(j.spring.law)) + " law), child frame";
  form.stiffness = add(table, "joint." + child_name + ".stiffness", "N m/rad", Shape::matrix3,
                       "spring stiffness of " + joint, j.spring.stiffness, ValidRange::non_negative());
  form.damping = add(table, "joint." + child_name + ".damping", "N m s/rad", Shape::matrix3, "damping of " + joint,
                     j.spring.damping, ValidRange::non_negative());
  form.law = j.spring.law;
}

// A sea state's parameters, axis by axis: base.AXIS.significant_height,
// .peak_period, .gamma (as its spectrum has them) and .phases.
void add_sea_state_parameters(ParameterTable& table, const SeaStateBase& sea, BaseForm& form) {
  form.offset =
      add(table, "base.offset", "m", Shape::vector3, "mean position of the sea-state base motion", sea.offset);
  static const char* axis_name[3] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    if (!sea.axes[axis] || sea.axes[axis]->wave_of >= 0) continue;  // a follower's wave is its source's
    const SeaStateAxis& a = *sea.axes[axis];
    const std::string name = "base." + std::string(axis_name[axis]) + ".";
    const std::string along = " of the sea state along " + std::string(axis_name[axis]);
    SeaAxisForm& f = form.sea[axis];
    if (a.spectrum != WaveSpectrum::tabulated) {
      f.significant_height =
          add(table, name + "significant_height", "m", Shape::scalar, "significant wave height Hs = 4 sqrt(m0)" + along,
              a.significant_height, ValidRange::positive());
      f.peak_period = add(table, name + "peak_period", "s", Shape::scalar,
                          "peak period Tp" + along + " (the components' frequencies stay the job's)", a.peak_period,
                          ValidRange::positive());
    }
    if (a.spectrum == WaveSpectrum::jonswap)
      f.gamma = add(table, name + "gamma", "1", Shape::scalar, "JONSWAP peak enhancement" + along, a.gamma,
                    ValidRange{1.0, false});
    f.phases = table.add(
        name + "phases", "rad", Shape::list,
        "phases of the " + std::to_string(a.components()) + " wave components" + along + " (one input each)", a.phases);
  }
}

void add_base_parameters(ParameterTable& table, const BaseMotionSpec& spec, BaseForm& form) {
  form.kind = spec;
  if (const auto* f = std::get_if<FixedBase>(&spec)) {
    form.position =
        add(table, "base.position", "m", Shape::vector3, "the fixed base point r0, inertial frame", f->position);
  } else if (const auto* c = std::get_if<ConstantAccelerationBase>(&spec)) {
    form.position =
        add(table, "base.position", "m", Shape::vector3, "base point r0(0), constant-acceleration base", c->position);
    form.velocity = add(table, "base.velocity", "m/s", Shape::vector3,
                        "base velocity r0'(0), constant-acceleration base", c->velocity);
    form.acceleration = add(table, "base.acceleration", "m/s^2", Shape::vector3,
                            "base acceleration r0'', constant-acceleration base", c->acceleration);
  } else if (const auto* h = std::get_if<HarmonicBase>(&spec)) {
    form.offset =
        add(table, "base.offset", "m", Shape::vector3, "mean position of the harmonic base motion", h->offset);
    static const char* axis_name[3] = {"x", "y", "z"};
    for (int axis = 0; axis < 3; ++axis) {
      for (std::size_t k = 0; k < h->axes[axis].size(); ++k) {
        const Harmonic& term = h->axes[axis][k];
        const std::string name = "base." + std::string(axis_name[axis]) + "[" + std::to_string(k + 1) + "].";
        const std::string which = "of term " + std::to_string(k + 1) + " of the base motion along " + axis_name[axis] +
                                  " (amplitude sin(2 pi frequency t + phase))";
        HarmonicForm offsets;
        offsets.amplitude = add(table, name + "amplitude", "m", Shape::scalar, "amplitude " + which, term.amplitude);
        offsets.frequency = add(table, name + "frequency", "Hz", Shape::scalar, "frequency " + which, term.frequency,
                                ValidRange::non_negative());
        offsets.phase = add(table, name + "phase", "rad", Shape::scalar, "phase " + which, term.phase);
        form.terms[axis].push_back(offsets);
      }
    }
  } else if (const auto* sea = std::get_if<SeaStateBase>(&spec)) {
    add_sea_state_parameters(table, *sea, form);
  } else {
    // A table is data, not parameters: validated and splined once here.
    form.tabulated = BaseMotion(spec);
  }
}

}  // namespace

ModelDefinition define_model(const ModelSpec& spec) {
  auto topology = std::make_shared<Topology>(make_topology(spec));  // names and tree shape first
  const Topology& tree = *topology;
  ModelDefinition d;
  d.body.resize(tree.n);
  d.joint.resize(tree.n);
  std::unordered_set<std::string> carries_at_lower_end;  // parents of joints that follow their length
  for (const JointSpec& j : spec.joints)
    if (j.on_parent_follows_length) carries_at_lower_end.insert(j.parent);
  for (int u = 0; u < tree.n; ++u) {
    const int i = tree.regular_index[u];
    const BodySpec& body = spec.bodies[u];
    const JointSpec& joint = spec.joints[tree.joint_of_user_body[u]];
    const Eigen::Vector4d q = joint.spring.reference.coeffs();
    if (!q.allFinite() || q.norm() < 1e-12)
      throw ModelError(
          "joint " + quoted(tree.joint_name[i]) + ": reference orientation must be a finite, non-zero quaternion",
          body.name);
    d.joint[i].reference = joint.spring.reference.normalized();
    // A joint point that follows a length sits on a cylinder's end.
    const int parent = tree.parent[i];
    if (joint.on_child_follows_length && body.solid != Solid::cylinder)
      throw ModelError("body " + quoted(body.name) +
                           ": its joint point follows its length (\"upper_end\"), "
                           "so it must be a cylinder (shape = \"cylinder\")",
                       body.name);
    if (joint.on_parent_follows_length &&
        (parent == kBase || spec.bodies[tree.user_index[parent]].solid != Solid::cylinder))
      throw ModelError("body " + quoted(body.name) +
                           ": its joint point on the parent follows the parent's "
                           "length (\"lower_end\"), so the parent must be a cylinder, not " +
                           (parent == kBase ? std::string("the base") : quoted(tree.body_name[parent])),
                       body.name);
    const bool ends_follow = joint.on_child_follows_length || carries_at_lower_end.count(body.name) > 0;
    add_body_parameters(d.parameters, body, ends_follow, d.body[i]);
    add_joint_parameters(d.parameters, body.name, tree.joint_name[i], joint, tree.parent[i] == kBase, d.joint[i]);
  }
  d.gravity = add(d.parameters, "gravity", "m/s^2", Shape::vector3, "uniform gravity, inertial frame", spec.gravity);
  add_base_parameters(d.parameters, spec.base_motion, d.base);

  auto body_of = [&](const std::string& name, const std::string& what, std::size_t k) {
    const int u = tree.find_user_body(name);
    if (u < 0)
      throw ModelError(what + " " + std::to_string(k + 1) + ": body " + quoted(name) + " is not a body of the model");
    return tree.regular_index[u];
  };
  for (std::size_t k = 0; k < spec.forces.size(); ++k) {
    const PointForce& f = spec.forces[k];
    const std::string name = "force[" + std::to_string(k + 1) + "].";
    const std::string on = " of force " + std::to_string(k + 1) + " on " + quoted(f.body);
    LoadForm load;
    load.body = body_of(f.body, "force", k);
    load.point = add(d.parameters, name + "point", "m", Shape::vector3,
                     "point of application" + on + ", from its CoM, its body frame", f.point);
    load.vector =
        add(d.parameters, name + "force", "N", Shape::vector3, "constant force" + on + ", inertial frame", f.force);
    d.forces.push_back(load);
  }
  for (std::size_t k = 0; k < spec.moments.size(); ++k) {
    const BodyMoment& m = spec.moments[k];
    LoadForm load;
    load.body = body_of(m.body, "moment", k);
    load.vector =
        add(d.parameters, "moment[" + std::to_string(k + 1) + "].moment", "N m", Shape::vector3,
            "constant moment " + std::to_string(k + 1) + " on " + quoted(m.body) + ", inertial frame", m.moment);
    d.moments.push_back(load);
  }
  d.topology = std::move(topology);
  return d;
}

Mat3 inertia_from_principal(const Vec3& moments, const Mat3& axes) {
  return axes * moments.asDiagonal() * axes.transpose();
}

}  // namespace treedyn
