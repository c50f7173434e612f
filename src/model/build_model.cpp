// build_model: validation, relabelling and the body-frame constants of
// section 3 of the theory page.
#include <unordered_map>

#include "common/error.hpp"
#include "model/model.hpp"
#include "model/tree.hpp"
#include "model/validate.hpp"

namespace treedyn {
namespace {

std::string body_label(const std::string& name) { return "body '" + name + "'"; }

void validate_bodies(const ModelSpec& spec) {
  for (const BodySpec& b : spec.bodies) {
    try {
      const std::string who = body_label(b.name);
      require_positive_mass(who, b.mass);
      require_valid_inertia(who, b.inertia);
    } catch (const ModelError& e) {
      throw ModelError(e.what(), b.name);
    }
  }
}

// Subtree masses, barycentres, b- and d-vectors and augmented inertias, all in
// the body's own frame.
void compute_constants(Model& m) {
  const int n = m.n;
  m.subtree_mass = m.mass;
  for (int i = n - 1; i >= 1; --i)
    if (m.parent[i] != kBase) m.subtree_mass[m.parent[i]] += m.subtree_mass[i];
  m.total_mass = m.subtree_mass[0];
  const double M = m.total_mass;

  m.barycentre.assign(n, Vec3::Zero());
  m.barycentre_to_inboard.assign(n, Vec3::Zero());
  m.augmented_inertia.assign(n, Mat3::Zero());
  m.branch_d.assign(n, Vec3::Zero());
  for (int i = 0; i < n; ++i) {
    const Vec3& c_ii = m.com_to_inboard_joint[i];
    // beta_i: barycentre of the augmented body, M - mu_i at the inboard joint
    // and mu_k at child k's joint.
    Vec3 moment = (M - m.subtree_mass[i]) * c_ii;
    for (int k : m.children[i]) moment += m.subtree_mass[k] * m.parent_com_to_joint[k];
    m.barycentre[i] = moment / M;
    m.barycentre_to_inboard[i] = c_ii - m.barycentre[i];  // b_i0 (38)

    // K_i (47)-(48): J_i, plus m_i at the CoM (d_ii = c_ii) and mu_k at child
    // k's joint (d_ij = c_ii - c_ik for all j in sub(k)), about the inboard joint.
    auto point_mass = [](double mass, const Vec3& d) {
      return Mat3(mass * (d.squaredNorm() * Mat3::Identity() - d * d.transpose()));
    };
    Mat3 K = m.inertia[i] + point_mass(m.mass[i], c_ii);
    for (int k : m.children[i]) {
      m.branch_d[k] = c_ii - m.parent_com_to_joint[k];  // d_ij, j in sub(k) (22)-(25)
      K += point_mass(m.subtree_mass[k], m.branch_d[k]);
    }
    m.augmented_inertia[i] = 0.5 * (K + K.transpose());
  }
}

}  // namespace

bool Model::is_ancestor(int i, int j) const {
  for (int a = parent[j]; a != kBase; a = parent[a])
    if (a == i) return true;
  return false;
}

Model build_model(const ModelSpec& spec) {
  const Topology topo = regular_order(spec);  // names and tree shape first
  validate_bodies(spec);
  require_finite("model", "gravity", spec.gravity);

  Model m;
  m.spec = spec;
  m.n = static_cast<int>(spec.bodies.size());
  m.parent = topo.parent;
  m.children = topo.children;
  m.depth = topo.depth;
  // The mass matrix keeps one 3x3 block per (body, strict ancestor) pair.
  long long path_blocks = 0;
  for (int d : topo.depth) path_blocks += d - 1;
  if (path_blocks > kMaxPathBlocks)
    throw ModelError("model: the tree is too deep for treedyn: " + std::to_string(path_blocks) +
                     " (body, ancestor) pairs, at most " + std::to_string(kMaxPathBlocks) +
                     " (a single chain of about 3100 bodies); shorten the chains");
  m.path_offset.assign(topo.depth.size() + 1, 0);
  for (std::size_t i = 0; i < topo.depth.size(); ++i)
    m.path_offset[i + 1] = m.path_offset[i] + topo.depth[i] - 1;
  m.user_index = topo.user_index;
  m.regular_index = topo.regular_index;
  m.gravity = spec.gravity;
  m.base_motion = BaseMotion(spec.base_motion);

  const int n = m.n;
  m.body_name.resize(n);
  m.joint_name.resize(n);
  m.mass.resize(n);
  m.inertia.resize(n);
  m.com_to_inboard_joint.resize(n);
  m.parent_com_to_joint.assign(n, Vec3::Zero());
  m.spring.resize(n);
  m.has_spring.assign(n, false);
  for (int i = 0; i < n; ++i) try {
    const int u = m.user_index[i];
    const BodySpec& body = spec.bodies[u];
    const JointSpec& joint = spec.joints[topo.joint_of_user_body[u]];
    m.body_name[i] = body.name;
    m.joint_name[i] = joint.name.empty() ? joint.parent + "-" + joint.child : joint.name;
    const std::string who = "joint '" + m.joint_name[i] + "'";
    m.mass[i] = body.mass;
    m.inertia[i] = 0.5 * (body.inertia + body.inertia.transpose());
    require_finite(who, "on_child", joint.on_child);
    m.com_to_inboard_joint[i] = joint.on_child;
    if (m.parent[i] != kBase) {
      require_finite(who, "on_parent", joint.on_parent);
      m.parent_com_to_joint[i] = joint.on_parent;
    }
    require_psd(who, "stiffness", joint.spring.stiffness);
    require_psd(who, "damping", joint.spring.damping);
    const Eigen::Vector4d q = joint.spring.reference.coeffs();
    if (!q.allFinite() || q.norm() < 1e-12)
      throw ModelError(who + ": reference orientation must be a finite, non-zero quaternion");
    m.spring[i] = joint.spring;
    m.spring[i].stiffness = 0.5 * (joint.spring.stiffness + joint.spring.stiffness.transpose());
    m.spring[i].damping = 0.5 * (joint.spring.damping + joint.spring.damping.transpose());
    m.spring[i].reference.normalize();
    m.has_spring[i] = !m.spring[i].stiffness.isZero(0.0) || !m.spring[i].damping.isZero(0.0);
  } catch (const ModelError& e) {
    throw ModelError(e.what(), spec.bodies[m.user_index[i]].name);
  }

  std::unordered_map<std::string, int> regular_by_name;
  for (int i = 0; i < n; ++i) regular_by_name[m.body_name[i]] = i;
  auto find_body = [&](const std::string& name, const std::string& what, std::size_t k) {
    const auto it = regular_by_name.find(name);
    if (it == regular_by_name.end())
      throw ModelError(what + " " + std::to_string(k + 1) + ": body '" + name +
                       "' is not a body of the model");
    return it->second;
  };
  m.point_forces.assign(n, {});
  m.applied_moment.assign(n, Vec3::Zero());
  for (std::size_t k = 0; k < spec.forces.size(); ++k) {
    const PointForce& f = spec.forces[k];
    const int i = find_body(f.body, "force", k);
    require_finite("force " + std::to_string(k + 1) + " on body '" + f.body + "'", "point", f.point);
    require_finite("force " + std::to_string(k + 1) + " on body '" + f.body + "'", "force", f.force);
    m.point_forces[i].push_back(f);
    m.has_point_forces = true;
  }
  for (std::size_t k = 0; k < spec.moments.size(); ++k) {
    const BodyMoment& mo = spec.moments[k];
    const int i = find_body(mo.body, "moment", k);
    require_finite("moment " + std::to_string(k + 1) + " on body '" + mo.body + "'", "moment", mo.moment);
    m.applied_moment[i] += mo.moment;
  }

  compute_constants(m);
  return m;
}

Mat3 inertia_from_principal(const Vec3& moments, const Mat3& axes) {
  return axes * moments.asDiagonal() * axes.transpose();
}

}  // namespace treedyn
