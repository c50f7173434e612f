// derive_model: a parameter vector into a Model, with the physical checks and
// the body-frame constants of section 3 of docs/wittenburg.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "common/error.hpp"
#include "model/definition.hpp"
#include "model/solids.hpp"
#include "model/validate.hpp"

namespace treedyn {
namespace {

Vec3 vec3(std::span<const double> p, int offset) { return {p[offset], p[offset + 1], p[offset + 2]}; }

Mat3 mat3(std::span<const double> p, int offset) {  // row-major
  Mat3 m;
  m << p[offset], p[offset + 1], p[offset + 2], p[offset + 3], p[offset + 4], p[offset + 5], p[offset + 6],
      p[offset + 7], p[offset + 8];
  return m;
}

std::string body_label(const std::string& name) { return "body '" + name + "'"; }

double volume(const BodyForm& f, std::span<const double> p) {
  switch (f.solid) {
    case Solid::box:
      return box_volume(vec3(p, f.size));
    case Solid::cylinder:
      return cylinder_volume(p[f.radius], p[f.length]);
    case Solid::sphere:
      return sphere_volume(p[f.radius]);
    case Solid::none:
      break;
  }
  return 0.0;
}

// Mass and central inertia (before symmetrising) of one body.
struct Inertial {
  double mass = 0.0;
  Mat3 inertia = Mat3::Zero();
};

Inertial solid_inertial(const BodyForm& f, std::span<const double> p, const std::string& who) {
  if (f.solid == Solid::box) {
    const Vec3 size = vec3(p, f.size);
    for (int a = 0; a < 3; ++a) require_positive(who, "size", "m", size[a]);
  } else {
    require_positive(who, "radius", "m", p[f.radius]);
    if (f.solid == Solid::cylinder) require_positive(who, "length", "m", p[f.length]);
  }
  Inertial out;
  if (f.density >= 0) {
    require_positive(who, "density", "kg/m^3", p[f.density]);
    out.mass = p[f.density] * volume(f, p);
  } else {
    out.mass = p[f.mass];
  }
  require_positive_mass(who, out.mass);
  Vec3 moments;
  switch (f.solid) {
    case Solid::box:
      moments = box_principal_moments(out.mass, vec3(p, f.size));
      break;
    case Solid::cylinder:
      moments = cylinder_principal_moments(out.mass, p[f.radius], p[f.length]);
      break;
    default:
      moments = sphere_principal_moments(out.mass, p[f.radius]);
      break;
  }
  out.inertia = moments.asDiagonal();
  return out;
}

void derive_bodies(const ModelDefinition& d, std::span<const double> p, Model& m) {
  const Topology& tree = *d.topology;
  for (int u = 0; u < tree.n; ++u) {  // the job's order: the first bad body is reported
    const int i = tree.regular_index[u];
    const BodyForm& f = d.body[i];
    const std::string& name = tree.body_name[i];
    try {
      const std::string who = body_label(name);
      Inertial b;
      if (f.solid == Solid::none) {
        b.mass = p[f.mass];
        b.inertia = mat3(p, f.inertia);
        require_positive_mass(who, b.mass);
      } else {
        b = solid_inertial(f, p, who);
      }
      const double scale = p[f.inertia_scale];
      require_positive(who, "inertia_scale", "1", scale);
      const Mat3 inertia = scale * b.inertia;
      require_valid_inertia(who, inertia);
      m.mass[i] = b.mass;
      m.inertia[i] = 0.5 * (inertia + inertia.transpose());
    } catch (const ModelError& e) {
      throw ModelError(e.what(), name);
    }
  }
}

// A chain link's length: its joints sit at its ends, (0, 0, +-L/2).
double link_length(const ModelDefinition& d, std::span<const double> p, int body) { return p[d.body[body].length]; }

void derive_joints(const ModelDefinition& d, std::span<const double> p, Model& m) {
  const Topology& tree = *d.topology;
  for (int i = 0; i < tree.n; ++i) try {
      const JointForm& f = d.joint[i];
      const std::string who = "joint '" + tree.joint_name[i] + "'";
      const int parent = tree.parent[i];
      const Vec3 on_child = f.on_child >= 0 ? vec3(p, f.on_child) : Vec3(0.0, 0.0, 0.5 * link_length(d, p, i));
      require_finite(who, "on_child", on_child);
      m.com_to_inboard_joint[i] = on_child;
      m.parent_com_to_joint[i].setZero();
      if (parent != kBase) {
        const Vec3 on_parent =
            f.on_parent >= 0 ? vec3(p, f.on_parent) : Vec3(0.0, 0.0, -0.5 * link_length(d, p, parent));
        require_finite(who, "on_parent", on_parent);
        m.parent_com_to_joint[i] = on_parent;
      }
      const Mat3 stiffness = mat3(p, f.stiffness), damping = mat3(p, f.damping);
      require_psd(who, "stiffness", stiffness);
      require_psd(who, "damping", damping);
      JointSpring& s = m.spring[i];
      s.stiffness = 0.5 * (stiffness + stiffness.transpose());
      s.damping = 0.5 * (damping + damping.transpose());
      s.reference = f.reference;
      s.law = f.law;
      m.has_spring[i] = !s.stiffness.isZero(0.0) || !s.damping.isZero(0.0);
    } catch (const ModelError& e) {
      throw ModelError(e.what(), tree.body_name[i]);
    }
}

BaseMotion derive_base(const BaseForm& f, std::span<const double> p) {
  if (std::holds_alternative<TabulatedBase>(f.kind)) return f.tabulated;
  BaseMotionSpec spec = f.kind;
  if (auto* fixed = std::get_if<FixedBase>(&spec)) {
    fixed->position = vec3(p, f.position);
  } else if (auto* c = std::get_if<ConstantAccelerationBase>(&spec)) {
    c->position = vec3(p, f.position);
    c->velocity = vec3(p, f.velocity);
    c->acceleration = vec3(p, f.acceleration);
  } else if (auto* h = std::get_if<HarmonicBase>(&spec)) {
    h->offset = vec3(p, f.offset);
    for (int axis = 0; axis < 3; ++axis)
      for (std::size_t k = 0; k < f.terms[axis].size(); ++k) {
        const HarmonicForm& t = f.terms[axis][k];
        h->axes[axis][k] = Harmonic{p[t.amplitude], p[t.frequency], p[t.phase]};
      }
  } else if (auto* sea = std::get_if<SeaStateBase>(&spec)) {
    sea->offset = vec3(p, f.offset);
    for (int axis = 0; axis < 3; ++axis) {
      if (!sea->axes[axis] || sea->axes[axis]->wave_of >= 0) continue;
      SeaStateAxis& a = *sea->axes[axis];
      const SeaAxisForm& form = f.sea[axis];
      if (form.significant_height >= 0) a.significant_height = p[form.significant_height];
      if (form.peak_period >= 0) a.peak_period = p[form.peak_period];
      if (form.gamma >= 0) a.gamma = p[form.gamma];
      std::copy_n(p.begin() + form.phases, a.phases.size(), a.phases.begin());
    }
    share_waves(sea->axes);
  }
  return BaseMotion(std::move(spec));
}

void derive_loads(const ModelDefinition& d, std::span<const double> p, Model& m) {
  const Topology& tree = *d.topology;
  for (auto& forces : m.point_forces) forces.clear();
  m.applied_moment.assign(tree.n, Vec3::Zero());
  m.has_point_forces = !d.forces.empty();
  for (std::size_t k = 0; k < d.forces.size(); ++k) {
    const LoadForm& f = d.forces[k];
    const std::string who = "force " + std::to_string(k + 1) + " on body '" + tree.body_name[f.body] + "'";
    BodyPointForce load{vec3(p, f.point), vec3(p, f.vector)};
    require_finite(who, "point", load.point);
    require_finite(who, "force", load.force);
    m.point_forces[f.body].push_back(load);
  }
  for (std::size_t k = 0; k < d.moments.size(); ++k) {
    const LoadForm& f = d.moments[k];
    const Vec3 moment = vec3(p, f.vector);
    require_finite("moment " + std::to_string(k + 1) + " on body '" + tree.body_name[f.body] + "'", "moment", moment);
    m.applied_moment[f.body] += moment;
  }
}

std::string format_value(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", v);
  return text;
}

// Subtree masses, barycentres, b- and d-vectors and augmented inertias, all in
// the body's own frame.
void compute_constants(Model& m) {
  const Topology& tree = *m.topology;
  const int n = m.n;
  m.subtree_mass = m.mass;
  for (int i = n - 1; i >= 1; --i)
    if (tree.parent[i] != kBase) m.subtree_mass[tree.parent[i]] += m.subtree_mass[i];
  m.total_mass = m.subtree_mass[0];
  const double M = m.total_mass;

  m.barycentre.assign(n, Vec3::Zero());
  m.barycentre_to_inboard.assign(n, Vec3::Zero());
  m.augmented_inertia.assign(n, Mat3::Zero());
  m.branch_d.assign(n, Vec3::Zero());
  m.inertia_about_joint.assign(n, Mat3::Zero());
  for (int i = 0; i < n; ++i) {
    const Vec3& c_ii = m.com_to_inboard_joint[i];
    // beta_i: barycentre of the augmented body, M - mu_i at the inboard joint
    // and mu_k at child k's joint.
    Vec3 moment = (M - m.subtree_mass[i]) * c_ii;
    for (int k : tree.children[i]) moment += m.subtree_mass[k] * m.parent_com_to_joint[k];
    m.barycentre[i] = moment / M;
    m.barycentre_to_inboard[i] = c_ii - m.barycentre[i];  // b_i0 (38)

    // K_i (47)-(48): J_i, plus m_i at the CoM (d_ii = c_ii) and mu_k at child
    // k's joint (d_ij = c_ii - c_ik for all j in sub(k)), about the inboard joint.
    auto point_mass = [](double mass, const Vec3& d) {
      return Mat3(mass * (d.squaredNorm() * Mat3::Identity() - d * d.transpose()));
    };
    Mat3 K = m.inertia[i] + point_mass(m.mass[i], c_ii);
    m.inertia_about_joint[i] = 0.5 * (K + K.transpose());  // H_i's own part (section 8)
    for (int k : tree.children[i]) {
      m.branch_d[k] = c_ii - m.parent_com_to_joint[k];  // d_ij, j in sub(k) (22)-(25)
      K += point_mass(m.subtree_mass[k], m.branch_d[k]);
    }
    m.augmented_inertia[i] = 0.5 * (K + K.transpose());
  }
  // Values each finite on their own can overflow in these sums (masses of
  // 1e308): the equations would be non-finite from t = 0.
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(m.subtree_mass[i]) || !m.augmented_inertia[i].allFinite() ||
        !m.inertia_about_joint[i].allFinite() || !m.barycentre_to_inboard[i].allFinite())
      throw ModelError("body '" + tree.body_name[i] +
                           "': its mass, inertia or joint points overflow double precision in the mass matrix "
                           "(mass of the subtree " +
                           format_value(m.subtree_mass[i]) + " kg); give SI values of a physical size",
                       tree.body_name[i]);
}

}  // namespace

void derive_model(const ModelDefinition& d, std::span<const double> p, Model& m) {
  if (p.size() != d.parameters.size())
    throw std::invalid_argument("derive_model: the parameter vector has the wrong size");
  const int n = d.topology->n;
  m.topology = d.topology;
  m.n = n;
  m.mass.resize(n);
  m.inertia.resize(n);
  m.com_to_inboard_joint.resize(n);
  m.parent_com_to_joint.resize(n);
  m.spring.resize(n);
  m.has_spring.resize(n);
  m.point_forces.resize(n);

  derive_bodies(d, p, m);
  m.gravity = vec3(p, d.gravity);
  require_finite("model", "gravity", m.gravity);
  m.base_motion = derive_base(d.base, p);
  derive_joints(d, p, m);
  derive_loads(d, p, m);
  compute_constants(m);
}

double solid_volume(const ModelDefinition& d, int body, std::span<const double> p) { return volume(d.body[body], p); }

Model build_model(const ModelSpec& spec) {
  const ModelDefinition definition = define_model(spec);
  Model model;
  derive_model(definition, definition.parameters.nominal(), model);
  return model;
}

}  // namespace treedyn
