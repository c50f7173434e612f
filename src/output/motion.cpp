#include "output/motion.hpp"

namespace treedyn {

OutputSpec motion_output() { return OutputSpec{{"com_position", "orientation", "joint_position"}, {}}; }

namespace {

// Box edges, cylinder (r, r, length), sphere (r, r, r) from the nominal parameters.
Vec3 nominal_dimensions(const BodyForm& form, std::span<const double> p) {
  switch (form.solid) {
    case Solid::box:
      return {p[form.size], p[form.size + 1], p[form.size + 2]};
    case Solid::cylinder:
      return {p[form.radius], p[form.radius], p[form.length]};
    case Solid::sphere:
      return {p[form.radius], p[form.radius], p[form.radius]};
    case Solid::none:
      break;
  }
  return Vec3::Zero();
}

}  // namespace

MotionScene motion_scene(const ModelDefinition& definition, const Model& model) {
  const Topology& tree = model.tree();
  const std::span<const double> nominal = definition.parameters.nominal();
  MotionScene s;
  for (int u = 0; u < model.n; ++u) {
    const int i = tree.regular_index[u];
    const int p = tree.parent[i];
    s.body.push_back(tree.body_name[i]);
    s.parent.push_back(p == kBase ? -1 : tree.user_index[p]);
    const BodyForm& form = definition.body[i];
    s.shape.push_back(form.solid == Solid::none ? "none" : std::string(name_in(kSolidNames, form.solid)));
    const Vec3 d = nominal_dimensions(form, nominal);
    const Vec3& c = model.com_to_inboard_joint[i];
    s.dimensions.insert(s.dimensions.end(), {d.x(), d.y(), d.z()});
    s.com_to_joint.insert(s.com_to_joint.end(), {c.x(), c.y(), c.z()});
    s.segments.push_back({2LL * u, 2LL * u + 1});
    if (s.parent.back() >= 0) s.segments.push_back({2LL * u, 2 * s.parent.back() + 1});
  }
  return s;
}

}  // namespace treedyn
