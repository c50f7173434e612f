// A description compiled once per run: the immutable tree, the named
// parameter vector with its nominal values, and the inputs that are not
// parameters (which bodies are solids, spring laws and reference
// orientations, the base motion's kind, a tabulated base's table). From it
// and any parameter vector, derive_model() builds a Model without looking at
// a name or re-checking the tree.
#pragma once

#include <array>
#include <memory>
#include <span>
#include <vector>

#include "model/base_motion.hpp"
#include "model/model.hpp"
#include "model/model_spec.hpp"
#include "model/parameters.hpp"
#include "model/topology.hpp"

namespace treedyn {

// Where a body's mass and inertia come from: offsets into the parameter
// vector, -1 where the body has no such parameter.
struct BodyForm {
  Solid solid = Solid::none;
  int mass = -1;           // body.NAME.mass; -1 for a solid given by its density
  int density = -1;        // body.NAME.density
  int size = -1;           // box edges (3)
  int radius = -1;         // cylinder, sphere
  int length = -1;         // cylinder
  int inertia = -1;        // explicit inertia (9, as given; symmetrised when derived)
  int inertia_scale = -1;  // multiplies the inertia (every body)
};

// Joint i, between body i and its parent.
struct JointForm {
  int on_child = -1;                  // body.NAME.joint_on_child (3); -1: (0, 0, +L/2) of the child's length
  int on_parent = -1;                 // body.NAME.joint_on_parent (3); -1: the base joint (no point), or
                                      // (0, 0, -L/2) of the parent's length (a chain link)
  int stiffness = -1;                 // joint.NAME.stiffness (9, as given)
  int damping = -1;                   // joint.NAME.damping (9, as given)
  Quat reference = Quat::Identity();  // unit
  SpringLaw law = SpringLaw::quaternion;
};

struct HarmonicForm {
  int amplitude = -1, frequency = -1, phase = -1;
};

// One axis of a sea state; -1 where its spectrum has no such parameter.
struct SeaAxisForm {
  int significant_height = -1, peak_period = -1, gamma = -1;
  int phases = -1;  // `components` entries
};

struct BaseForm {
  BaseMotionSpec kind = FixedBase{};  // which motion and how many terms; its numbers are parameters
  int position = -1, velocity = -1, acceleration = -1, offset = -1;
  std::array<std::vector<HarmonicForm>, 3> terms;
  std::array<SeaAxisForm, 3> sea;  // a sea state's spectra (its band and RAO are fixed)
  BaseMotion tabulated;            // a tabulated base: its table is fixed, not parameters
};

// A constant force or moment on one body.
struct LoadForm {
  int body = -1;    // regular index
  int point = -1;   // force[K].point (3), forces only
  int vector = -1;  // force[K].force or moment[K].moment (3)
};

struct ModelDefinition {
  std::shared_ptr<const Topology> topology;
  ParameterTable parameters;
  std::vector<BodyForm> body;    // regular order
  std::vector<JointForm> joint;  // regular order
  int gravity = -1;
  BaseForm base;
  std::vector<LoadForm> forces, moments;  // in the description's order
};

// Checks the tree, the names and the inputs that are not parameters, and
// lays out the parameters. Throws ModelError naming the body or joint.
ModelDefinition define_model(const ModelSpec& spec);

// The model for one parameter vector (e.g. definition.parameters.nominal()):
// derived constants, plus the physical checks on the values (positive mass
// and dimensions, a positive definite inertia obeying the triangle
// inequality, positive semi-definite springs, finite points, a valid base
// motion). Throws ModelError naming the body or joint. Reuses `out`'s storage.
void derive_model(const ModelDefinition& definition, std::span<const double> parameters, Model& out);

// Volume of the solid body `body` (regular index) for these parameters, m^3;
// 0 for a body whose inertia is given explicitly.
double solid_volume(const ModelDefinition& definition, int body, std::span<const double> parameters);

}  // namespace treedyn
