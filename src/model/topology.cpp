#include "model/topology.hpp"

#include <string>
#include <unordered_map>

#include "common/error.hpp"

namespace treedyn {
namespace {

std::string quoted(const std::string& s) { return "'" + s + "'"; }

std::string joint_label(const JointSpec& j, std::size_t index) {
  if (!j.name.empty()) return "joint " + quoted(j.name);
  return "joint " + std::to_string(index + 1) + " (" + quoted(j.parent) + " -> " + quoted(j.child) + ")";
}

// Body names to their user index; names must be unique and not "base".
std::unordered_map<std::string, int> index_names(const ModelSpec& spec) {
  std::unordered_map<std::string, int> by_name;
  for (int b = 0; b < static_cast<int>(spec.bodies.size()); ++b) {
    const std::string& name = spec.bodies[b].name;
    if (name.empty()) throw ModelError("body " + std::to_string(b + 1) + ": name is empty");
    if (name == kBaseName)
      throw ModelError("body " + std::to_string(b + 1) + ": the name " + quoted(kBaseName) +
                       " is reserved for the moving base point");
    if (!by_name.emplace(name, b).second)
      throw ModelError("body " + quoted(name) + ": name used by more than one body", name);
  }
  return by_name;
}

// Who hangs from whom, in user indices: each body's joint and parent, and
// the bodies on the base.
struct Links {
  std::vector<int> joint_of, parent_user, on_base;
};

Links link_bodies(const ModelSpec& spec, const std::unordered_map<std::string, int>& by_name) {
  const int n = static_cast<int>(spec.bodies.size());
  Links l{std::vector<int>(n, -1), std::vector<int>(n, kBase), {}};
  for (std::size_t j = 0; j < spec.joints.size(); ++j) {
    const JointSpec& joint = spec.joints[j];
    const std::string who = joint_label(joint, j);
    const auto child = by_name.find(joint.child);
    if (child == by_name.end())
      throw ModelError(who + ": child " + quoted(joint.child) + " is not a body of the model", joint.child);
    if (joint.parent == joint.child)
      throw ModelError("body " + quoted(joint.child) + ": " + who +
                           " makes it its own parent; a joint must connect two different bodies",
                       joint.child);
    int parent = kBase;
    if (joint.parent != kBaseName) {
      const auto p = by_name.find(joint.parent);
      if (p == by_name.end())
        throw ModelError(who + ": parent " + quoted(joint.parent) + " is neither a body nor " + quoted(kBaseName),
                         joint.child);
      parent = p->second;
    }
    const int c = child->second;
    if (l.joint_of[c] >= 0)
      throw ModelError("body " + quoted(joint.child) + ": has two joints to a parent (" +
                           joint_label(spec.joints[l.joint_of[c]], l.joint_of[c]) + " and " + who +
                           "); in a tree every body has exactly one",
                       joint.child);
    l.joint_of[c] = static_cast<int>(j);
    l.parent_user[c] = parent;
    if (parent == kBase) l.on_base.push_back(c);
  }
  return l;
}

// Every body has a joint, and exactly one hangs from the base.
void require_one_root(const ModelSpec& spec, const Links& l) {
  for (std::size_t b = 0; b < spec.bodies.size(); ++b)
    if (l.joint_of[b] < 0)
      throw ModelError("body " + quoted(spec.bodies[b].name) +
                           ": unreachable, no joint has it as its child; every body needs a joint to its parent",
                       spec.bodies[b].name);
  if (l.on_base.empty())
    throw ModelError("body " + quoted(spec.bodies[0].name) + ": no body is attached to " + quoted(kBaseName) +
                         ", so the chain of parents from " + quoted(spec.bodies[0].name) +
                         " never reaches it (a cycle); exactly one joint must have parent " + quoted(kBaseName),
                     spec.bodies[0].name);
  if (l.on_base.size() > 1)
    throw ModelError("body " + quoted(spec.bodies[l.on_base[1]].name) + ": a second body on " + quoted(kBaseName) +
                         " (the first is " + quoted(spec.bodies[l.on_base[0]].name) +
                         "); exactly one body may be attached to the base",
                     spec.bodies[l.on_base[1]].name);
}

// The regular order: depth-first preorder from the base, children in the
// user's order. Bodies never reached hang in a loop of parents.
void order_preorder(const ModelSpec& spec, const Links& l, Topology& topo) {
  const int n = static_cast<int>(spec.bodies.size());
  std::vector<std::vector<int>> user_children(n);
  for (int b = 0; b < n; ++b)
    if (l.parent_user[b] != kBase) user_children[l.parent_user[b]].push_back(b);
  topo.regular_index.assign(n, -1);
  std::vector<int> stack{l.on_base[0]};
  while (!stack.empty()) {
    const int b = stack.back();
    stack.pop_back();
    topo.regular_index[b] = static_cast<int>(topo.user_index.size());
    topo.user_index.push_back(b);
    for (auto it = user_children[b].rbegin(); it != user_children[b].rend(); ++it) stack.push_back(*it);
  }
  for (int b = 0; b < n; ++b)
    if (topo.regular_index[b] < 0)
      throw ModelError("body " + quoted(spec.bodies[b].name) +
                           ": not connected to the base, its chain of parents forms a cycle; the "
                           "joints must form a tree",
                       spec.bodies[b].name);
}

// Parents, children, depths and names in the regular order.
void fill_regular(const ModelSpec& spec, const Links& l, Topology& topo) {
  const int n = static_cast<int>(spec.bodies.size());
  topo.n = n;
  topo.parent.resize(n);
  topo.children.assign(n, {});
  topo.depth.resize(n);
  topo.body_name.resize(n);
  topo.joint_name.resize(n);
  for (int i = 0; i < n; ++i) {
    const int u = topo.user_index[i];
    const int pu = l.parent_user[u];
    topo.parent[i] = pu == kBase ? kBase : topo.regular_index[pu];
    topo.depth[i] = pu == kBase ? 1 : topo.depth[topo.parent[i]] + 1;
    if (topo.parent[i] != kBase) topo.children[topo.parent[i]].push_back(i);
    const JointSpec& joint = spec.joints[l.joint_of[u]];
    topo.body_name[i] = spec.bodies[u].name;
    topo.joint_name[i] = joint.name.empty() ? joint.parent + "-" + joint.child : joint.name;
  }
}

}  // namespace

Topology make_topology(const ModelSpec& spec) {
  if (spec.bodies.empty()) throw ModelError("model: no bodies; a tree needs at least one body");
  const Links links = link_bodies(spec, index_names(spec));
  require_one_root(spec, links);
  Topology topo;
  topo.joint_of_user_body = links.joint_of;
  order_preorder(spec, links, topo);
  fill_regular(spec, links, topo);
  return topo;
}

bool Topology::is_ancestor(int i, int j) const {
  for (int a = parent[j]; a != kBase; a = parent[a])
    if (a == i) return true;
  return false;
}

int Topology::find_user_body(const std::string& name) const {
  for (int u = 0; u < n; ++u)
    if (user_body_name(u) == name) return u;
  return -1;
}

}  // namespace treedyn
