// Section readers of the job file (internal to src/job and the designs' readers in src/designs/).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "job/toml_view.hpp"
#include "model/definition.hpp"
#include "model/initial_state.hpp"
#include "model/model_spec.hpp"
#include "sampling/perturbation.hpp"

namespace treedyn {

// The largest model treedyn supports (docs/jobs.md, "[[body]]"); larger ones are
// refused before anything is built.
inline constexpr long long kMaxBodies = 10000;

// An orientation table {type = "quaternion" | "axis_angle" | "euler313" |
// "bryant123", ...}; angles need unit = "deg" or "rad".
Mat3 read_orientation(const TomlView& table);
// {value = [x, y, z], frame = "inertial" | "body", unit = "rad/s" | "deg/s"}
// turned into the inertial frame with the body's orientation.
struct AngularVelocityInput {
  Vec3 inertial = Vec3::Zero();
  std::optional<Vec3> body;  // the components, when given in the body's frame
};
AngularVelocityInput read_angular_velocity(const TomlView& table, const Mat3& orientation);

// The bodies of [[body]] and [[chain]] with their joints and initial state,
// in file order. `where` maps each body name to the table that defined it.
struct ReadBodies {
  std::vector<BodySpec> bodies;
  std::vector<JointSpec> joints;
  InitialState initial;
  std::map<std::string, const toml::node*> where;
};
ReadBodies read_bodies(const TomlView& root);

BaseMotionSpec read_base(const TomlView& base);
// [base] type = "sea_state" (read_sea_state.cpp).
SeaStateBase read_sea_state(const TomlView& base);

void read_loads(const TomlView& root, ModelSpec& spec);

// `target` and `mode` of a [[ensemble.perturbation]] or [[sample.input]]
// table, resolved against the model (sampling/targets.hpp).
sampling::Perturbation read_target(const TomlView& table, const ModelDefinition& model);

struct EnsembleSpec;
// [[ensemble.group]] into spec.sobol_units (every input alone without one)
// and [[ensemble.correlation]] into spec.correlations, after the
// perturbations and the design are read (read_input_relations.cpp).
void read_groups(const TomlView& ensemble, EnsembleSpec& spec);
void read_correlations(const TomlView& ensemble, EnsembleSpec& spec);
// Refuses more than `max_runs` runs (the exact sums' limit) at `t`'s samples.
void refuse_more_runs_than(const TomlView& t, std::uint64_t runs, std::uint64_t max_runs);
// The index of the [[ensemble.response]] that `t`'s `response` names.
std::size_t named_response(const TomlView& t, const EnsembleSpec& spec);

}  // namespace treedyn
