#include "sampling/targets.hpp"

#include <optional>
#include <string_view>
#include <tuple>

namespace treedyn::sampling {
namespace {

using Kind = Perturbation::Kind;

constexpr const char* kPatterns =
    "allowed targets: any parameter of the model by name (body.NAME.mass, body.NAME.density, "
    "body.NAME.length, body.NAME.radius, body.NAME.size.AXIS, body.NAME.inertia_scale, "
    "body.NAME.joint_on_child.AXIS, body.NAME.joint_on_parent.AXIS, joint.CHILD.stiffness, "
    "joint.CHILD.damping, gravity.AXIS, base.AXIS[K].amplitude, .frequency, .phase, "
    "base.acceleration.AXIS, base.AXIS.significant_height, .peak_period, .gamma, .phases (a sea state), "
    "force[K].force.AXIS, ...; `treedyn check --parameters JOB` lists "
    "them) and the initial state (body.NAME.orientation, body.NAME.rotation.AXIS, "
    "body.NAME.angular_velocity.AXIS); AXIS = x, y or z, K counts from 1";

std::optional<int> axis_of(std::string_view text) {
  if (text == "x") return 0;
  if (text == "y") return 1;
  if (text == "z") return 2;
  return std::nullopt;
}

std::string quoted(std::string_view s) { return "'" + std::string(s) + "'"; }

// The body whose name follows `prefix` in the target ("body.NAME.rest"), and
// the rest; the longest matching name wins (names may hold dots).
struct BodyPart {
  int user = -1;
  std::string name, rest;
};
BodyPart body_part(const Topology& tree, std::string_view target, std::string_view prefix) {
  BodyPart best;
  if (target.substr(0, prefix.size()) != prefix) return best;
  const std::string_view after = target.substr(prefix.size());
  for (int u = 0; u < tree.n; ++u) {
    const std::string& name = tree.user_body_name(u);
    if (after.size() > name.size() && after.substr(0, name.size()) == name && after[name.size()] == '.' &&
        name.size() > best.name.size())
      best = {u, name, std::string(after.substr(name.size() + 1))};
  }
  return best;
}

// The initial-state targets of body `u`, from the rest of "body.NAME.rest".
std::optional<Target> state_target(const Topology& tree, int u, std::string_view rest) {
  const std::string& name = tree.user_body_name(u);
  if (rest == "orientation")
    return Target{.kind = Kind::orientation,
                  .first = u,
                  .unit = "rad",
                  .enters = "a small rotation of the initial orientation of " + quoted(name) +
                            " about inertial axes (rotation vector)"};
  for (const auto& [field, kind, unit] : {std::tuple{"rotation.", Kind::rotation, "rad"},
                                          std::tuple{"angular_velocity.", Kind::angular_velocity, "rad/s"}}) {
    const std::string_view f(field);
    if (rest.substr(0, f.size()) != f) continue;
    const auto axis = axis_of(rest.substr(f.size()));
    if (!axis) throw TargetError("axis " + quoted(rest.substr(f.size())) + " is not allowed; use x, y or z");
    const std::string axis_name(rest.substr(f.size()));
    const std::string what =
        kind == Kind::rotation
            ? "an extra rotation of the initial orientation of " + quoted(name) + " about the inertial " + axis_name +
                  " axis"
            : "the inertial " + axis_name + " component of the initial angular velocity of " + quoted(name);
    return Target{.kind = kind, .first = u, .axis = *axis, .unit = unit, .enters = what};
  }
  return std::nullopt;
}

// The mass of a solid given by its density, or the density of one given by
// its mass: the same input in the other unit, converted at the nominal
// dimensions (the written one is what stays when a dimension changes).
std::optional<Target> other_mass_target(const ModelDefinition& d, int u, std::string_view rest) {
  const Topology& tree = *d.topology;
  const int i = tree.regular_index[u];
  const BodyForm& body = d.body[i];
  if (body.solid == Solid::none) return std::nullopt;
  const double volume = solid_volume(d, i, d.parameters.nominal());
  const std::string name = quoted(tree.user_body_name(u));
  const std::string solid(name_in(kSolidNames, body.solid));
  if (rest == "mass" && body.density >= 0)
    return Target{.first = body.density,
                  .factor = 1.0 / volume,
                  .unit = "kg",
                  .enters = "mass of the homogeneous " + solid + " " + name +
                            ", set through its density (the job gives the density): density = "
                            "mass / nominal volume, and its inertia follows; a perturbed dimension "
                            "keeps the density"};
  if (rest == "density" && body.mass >= 0)
    return Target{.first = body.mass,
                  .factor = volume,
                  .unit = "kg/m^3",
                  .enters = "density of the homogeneous " + solid + " " + name +
                            ", set through its mass (the job gives the mass): mass = density x "
                            "nominal volume, and its inertia follows; a perturbed dimension keeps "
                            "the mass"};
  return std::nullopt;
}

// Why body.NAME.FIELD is not a parameter of this model, when it is one that
// other bodies can have.
std::string why_absent(const ModelDefinition& d, int u, const std::string& field) {
  const Topology& tree = *d.topology;
  const int i = tree.regular_index[u];
  const BodyForm& body = d.body[i];
  const JointForm& joint = d.joint[i];
  const std::string name = quoted(tree.user_body_name(u));
  const std::string prefix = "body." + tree.user_body_name(u) + ".";
  const std::string solid(name_in(kSolidNames, body.solid));
  if (field == "density")
    return "the inertia of " + name + " is given explicitly, so it has no density; perturb " + prefix +
           "mass (mass only) or " + prefix + "inertia_scale";
  if (field == "length" || field == "radius" || field.rfind("size", 0) == 0 || field == "size") {
    if (body.solid == Solid::none)
      return name + " has no shape (its inertia is given explicitly), so it has no " + field;
    return name + " is a " + solid + ": its dimensions are " +
           (body.solid == Solid::box      ? prefix + "size.x, .y, .z"
            : body.solid == Solid::sphere ? prefix + "radius"
                                          : prefix + "radius and " + prefix + "length");
  }
  if (field == "inertia" && body.solid != Solid::none)
    return name + " is a homogeneous " + solid + ": its inertia follows from its mass and " +
           "dimensions; perturb those, or " + prefix + "inertia_scale";
  if (field.rfind("joint_on_child", 0) == 0 && joint.on_child < 0)
    return "the joint point of " + name +
           " is the upper end of the cylinder (0, 0, +L/2) and "
           "follows its length; perturb " +
           prefix + "length";
  if (field.rfind("joint_on_parent", 0) == 0 && joint.on_parent < 0)
    return tree.parent[i] == kBase ? name +
                                         " hangs from the base: its joint point there is the base point r0; perturb "
                                         "the [base] motion instead (e.g. base.position.AXIS)"
                                   : "the joint of " + name + " is the lower end of the cylinder " +
                                         quoted(tree.body_name[tree.parent[i]]) +
                                         " (0, 0, -L/2) and follows its "
                                         "length; perturb body." +
                                         tree.body_name[tree.parent[i]] + ".length";
  return "";
}

std::string parameters_of_body(const ModelDefinition& d, int u) {
  const std::string prefix = "body." + d.topology->user_body_name(u) + ".";
  const std::string joint = "joint." + d.topology->user_body_name(u) + ".";
  std::string out;
  for (const Parameter& p : d.parameters.parameters())
    if (p.name.rfind(prefix, 0) == 0 || p.name.rfind(joint, 0) == 0)
      out += (out.empty() ? "" : ", ") + p.name + (p.shape == ParameterShape::vector3 ? ".AXIS" : "");
  const BodyForm& body = d.body[d.topology->regular_index[u]];
  if (body.solid != Solid::none) out += ", " + prefix + (body.density >= 0 ? "mass" : "density");
  return out + ", " + prefix + "orientation, " + prefix + "rotation.AXIS, " + prefix + "angular_velocity.AXIS";
}

// This job's parameters whose names start with `prefix`, vectors as .AXIS.
std::string parameters_named(const ModelDefinition& d, const std::string& prefix) {
  std::string out;
  for (const Parameter& p : d.parameters.parameters())
    if (p.name.rfind(prefix, 0) == 0)
      out += (out.empty() ? "" : ", ") + p.name + (p.shape == ParameterShape::vector3 ? ".AXIS" : "");
  return out;
}

std::string base_type(const ModelDefinition& d) {
  if (std::holds_alternative<FixedBase>(d.base.kind)) return "fixed";
  if (std::holds_alternative<ConstantAccelerationBase>(d.base.kind)) return "constant_acceleration";
  if (std::holds_alternative<HarmonicBase>(d.base.kind)) return "harmonic";
  if (std::holds_alternative<SeaStateBase>(d.base.kind)) return "sea_state";
  return "tabulated";
}

// base.* that this job's base does not have: which base it is, and what it has.
std::string why_not_base(const ModelDefinition& d, const std::string& target) {
  const std::string type = base_type(d);
  if (type == "tabulated")
    return quoted(target) +
           " is not a target of this job: its [base] is tabulated, and a table is data, not "
           "parameters; use type = \"harmonic\" or \"constant_acceleration\" to perturb the base motion";
  const std::string has = parameters_named(d, "base.");
  std::string hint;
  if (target.rfind("base.position", 0) == 0 && type == "harmonic")
    hint = " (a harmonic base's mean position is base.offset.AXIS)";
  else if (target.rfind("base.offset", 0) == 0)
    hint = " (base.offset is a harmonic base's mean position; this base's point is base.position.AXIS)";
  else if (target.size() > 6 && target[6] == '[' && type != "harmonic")
    hint = " (terms AXIS[K] belong to a harmonic base)";
  else if (target.size() > 6 && target[6] == '[')
    hint = " (K counts from 1 up to the number of terms on that axis)";
  else if (type == "sea_state" && target.size() > 7 && target[6] == '.')
    hint =
        " (a sea state's targets are those of the axes it has a table for; a tabulated spectrum has only "
        "phases, and only JONSWAP has gamma)";
  else if (type != "sea_state" &&
           (target.find(".phases") != std::string::npos || target.find(".significant_height") != std::string::npos ||
            target.find(".peak_period") != std::string::npos))
    hint = " (phases, significant_height and peak_period belong to a [base] of type \"sea_state\")";
  return quoted(target) + " is not a target of this job, whose [base] is " + type + hint +
         "; its base targets: " + (has.empty() ? std::string("none") : has);
}

// force[K].* or moment[K].* beyond the job's [[force]] or [[moment]] tables.
std::string why_not_load(const ModelDefinition& d, const std::string& target, const std::string& table,
                         std::size_t count) {
  if (count == 0)
    return quoted(target) + " is not a target of this job: it has no [[" + table + "]]; add one to perturb it";
  return quoted(target) + " is not a target of this job, which has " + std::to_string(count) + " [[" + table +
         "]] table" + (count == 1 ? "" : "s") + " (K counts from 1); its " + table +
         " targets: " + parameters_named(d, table + "[");
}

// A target of a kind other jobs have but this one does not: why, and what
// it has instead; "" when the target is of no known kind.
std::string why_not_in_this_job(const ModelDefinition& d, const std::string& target) {
  if (target.rfind("base.", 0) == 0) return why_not_base(d, target);
  if (target.rfind("force[", 0) == 0) return why_not_load(d, target, "force", d.forces.size());
  if (target.rfind("moment[", 0) == 0) return why_not_load(d, target, "moment", d.moments.size());
  return "";
}

}  // namespace

Target resolve_target(const ModelDefinition& d, const std::string& target) {
  const Topology& tree = *d.topology;
  const ParameterTable& table = d.parameters;
  // A parameter by its name, or a component NAME.AXIS of a vector.
  if (const Parameter* p = table.find(target)) {
    if (p->shape == ParameterShape::vector3)
      throw TargetError(quoted(target) + " is a vector: perturb one component, " + target + ".x, " + target + ".y or " +
                        target + ".z");
    if (p->shape == ParameterShape::list)
      return Target{
          .kind = Kind::parameter_list, .first = p->offset, .entries = p->size(), .unit = p->unit, .enters = p->enters};
    return Target{.first = p->offset, .entries = p->size(), .unit = p->unit, .enters = p->enters};
  }
  if (const auto dot = target.rfind('.'); dot != std::string::npos) {
    if (const Parameter* p = table.find(std::string_view(target).substr(0, dot));
        p && p->shape == ParameterShape::vector3) {
      const auto axis = axis_of(std::string_view(target).substr(dot + 1));
      if (!axis) throw TargetError("axis " + quoted(target.substr(dot + 1)) + " is not allowed; use x, y or z");
      return Target{.first = p->offset + *axis,
                    .unit = p->unit,
                    .enters = p->enters + " (" + target.substr(dot + 1) + " component)"};
    }
  }
  // The initial state, or an explanation.
  if (target.rfind("body.", 0) == 0 || target.rfind("joint.", 0) == 0) {
    const bool joint = target[0] == 'j';
    const BodyPart part = body_part(tree, target, joint ? "joint." : "body.");
    if (part.user < 0) {
      const std::string rest = target.substr(joint ? 6 : 5);
      throw TargetError(quoted(rest.substr(0, rest.find('.'))) + " is not a body of the model" +
                        (joint ? " (a joint is named by its child body)" : ""));
    }
    if (!joint) {
      if (auto state = state_target(tree, part.user, part.rest)) return *state;
      if (auto other = other_mass_target(d, part.user, part.rest)) return *other;
    }
    const std::string why = joint ? "" : why_absent(d, part.user, part.rest);
    if (!why.empty()) throw TargetError(quoted(target) + " is not a target of this job: " + why);
    throw TargetError(quoted(target) + " is not a target; allowed targets for body " + quoted(part.name) + ": " +
                      parameters_of_body(d, part.user));
  }
  if (const std::string why = why_not_in_this_job(d, target); !why.empty()) throw TargetError(why);
  throw TargetError(quoted(target) + " is not a target; " + kPatterns);
}

void aim(Perturbation& p, const ModelDefinition& model) {
  const Target target = resolve_target(model, p.target);
  p.kind = target.kind;
  p.first = target.first;
  p.entries = target.entries;
  p.factor = target.factor;
  p.axis = target.axis;
  p.si_unit = target.unit;
  p.enters = target.enters;
}

}  // namespace treedyn::sampling
