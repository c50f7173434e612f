// [[body]], [[chain]], [base], [[force]], [[moment]].
#include <algorithm>
#include <cmath>
#include <numbers>

#include "job/readers.hpp"

namespace treedyn {
namespace {

double positive(const TomlView& t, std::string_view key, const char* unit) {
  const double v = t.required_number(key);
  if (!(v > 0.0)) t.fail(key, format_number(v) + " is not allowed; must be positive (" + unit + ")");
  return v;
}

// `mass` or `density` (exactly one of them) of a solid.
void read_mass_or_density(const TomlView& t, BodySpec& body) {
  const bool has_mass = t.has("mass"), has_density = t.has("density");
  if (has_mass == has_density)
    t.fail(has_mass ? "density" : "mass",
           "give exactly one of 'mass' (kg) or 'density' (kg/m^3) for a body with a shape");
  if (has_mass)
    body.mass = positive(t, "mass", "kg");
  else
    body.density = positive(t, "density", "kg/m^3");
}

void read_mass_and_inertia(const TomlView& t, BodySpec& body) {
  const auto shape = t.string("shape");
  if (shape) {
    for (std::string_view k : {"inertia", "principal_moments", "principal_axes"})
      if (t.has(k)) t.fail(k, "not allowed together with 'shape': the shape defines the inertia");
    if (!parse_in(kSolidNames, *shape, body.solid))
      t.fail("shape", "\"" + *shape + "\" is not a shape; allowed: " + choices(kSolidNames));
    if (body.solid == Solid::box) {
      const auto size = t.vec3("size");
      if (!size) t.fail("size", "missing: a box needs size = [x, y, z] in m");
      if (!(size->minCoeff() > 0.0)) t.fail("size", "every edge must be positive (m)");
      body.size = *size;
    } else {
      body.radius = positive(t, "radius", "m");
      if (body.solid == Solid::cylinder) body.length = positive(t, "length", "m");
    }
    for (std::string_view k : {"size", "radius", "length"}) {
      const bool used = k == "size"     ? body.solid == Solid::box
                        : k == "radius" ? body.solid != Solid::box
                                        : body.solid == Solid::cylinder;
      if (t.has(k) && !used)
        t.fail(k,
               "not a dimension of a " + *shape + " (a box has size, a cylinder radius and length, a sphere radius)");
    }
    read_mass_or_density(t, body);
    return;
  }
  for (std::string_view k : {"size", "radius", "length", "density"})
    if (t.has(k)) t.fail(k, "only meaningful with 'shape' (\"box\", \"cylinder\" or \"sphere\")");
  if (!t.has("mass")) t.fail("mass", "missing required field: the body's mass in kg (or give a 'shape')");
  body.mass = positive(t, "mass", "kg");
  const bool full = t.has("inertia"), principal = t.has("principal_moments");
  if (full == principal)
    t.fail(full ? "principal_moments" : "inertia",
           "give exactly one of 'inertia' (3x3, kg m^2) or 'principal_moments' ([A, B, C], kg m^2)");
  if (full) {
    body.inertia = *t.mat3_or_scalar("inertia");
    return;
  }
  const Vec3 moments = *t.vec3("principal_moments");
  Mat3 axes = Mat3::Identity();
  if (const auto given = t.mat3_or_scalar("principal_axes")) {
    axes = given->transpose();  // rows in the file are the axes; columns here
    if (!(axes.transpose() * axes).isApprox(Mat3::Identity(), 1e-9) || axes.determinant() < 0.0)
      t.fail("principal_axes", "the three axes must be orthonormal and right-handed");
  }
  body.inertia = inertia_from_principal(moments, axes);
}

JointSpring read_spring(const TomlView& t) {
  t.check_keys({"stiffness", "damping", "reference", "law"});
  JointSpring s;
  if (auto law = t.string("law"); law && !parse_in(kSpringLawNames, *law, s.law))
    t.fail("law", "\"" + *law + "\" is not a spring law; allowed: " + choices(kSpringLawNames));
  if (auto k = t.mat3_or_scalar("stiffness")) s.stiffness = *k;
  if (auto c = t.mat3_or_scalar("damping")) s.damping = *c;
  if (auto r = t.subtable("reference")) s.reference = Quat(read_orientation(*r));
  return s;
}

// A joint point: [x, y, z] in m, or the end of a cylinder that the point
// follows when the cylinder's length changes: `end` is "upper_end" for
// joint_on_child (0, 0, +L/2 of this body) or "lower_end" for
// joint_on_parent (0, 0, -L/2 of the parent). Whether that body is a
// cylinder is checked with the whole tree (define_model).
Vec3 read_joint_point(const TomlView& t, std::string_view key, std::string_view end, bool& follows) {
  if (t.has(key) && t.table().get(key)->is_string()) {
    if (*t.string(key) != end)
      t.fail(key, "\"" + *t.string(key) + "\" is not allowed; give [x, y, z] in m, or \"" + std::string(end) +
                      "\" (the cylinder's end, moving with its length)");
    follows = true;
    return Vec3::Zero();
  }
  return t.vec3(key).value_or(Vec3::Zero());
}

void read_state(const TomlView& t, ReadBodies& out) {
  Mat3 A = Mat3::Identity();
  if (auto o = t.subtable("orientation")) A = read_orientation(*o);
  AngularVelocityInput w;
  if (auto v = t.subtable("angular_velocity")) w = read_angular_velocity(*v, A);
  out.initial.rotation.push_back(A);
  out.initial.angular_velocity.push_back(w.inertial);
  out.initial.body_frame_spin.push_back(w.body);
}

void read_body(const TomlView& t, ReadBodies& out) {
  t.check_keys({"name", "parent", "joint_on_parent", "joint_on_child", "mass", "density", "inertia",
                "principal_moments", "principal_axes", "shape", "size", "radius", "length", "orientation",
                "angular_velocity", "spring"});
  BodySpec body;
  body.name = t.required_string("name");
  if (body.name.empty()) t.fail("name", "must not be empty");
  if (body.name == kBaseName)
    t.fail("name", "the name \"base\" is reserved for the moving base point; choose another name");
  read_mass_and_inertia(t, body);
  JointSpec joint;
  joint.child = body.name;
  const auto parent = t.string("parent");
  if (!parent) t.fail("parent", "missing required field: the parent body's name, or \"base\"");
  joint.parent = *parent;
  joint.on_parent = read_joint_point(t, "joint_on_parent", "lower_end", joint.on_parent_follows_length);
  joint.on_child = read_joint_point(t, "joint_on_child", "upper_end", joint.on_child_follows_length);
  if (auto s = t.subtable("spring")) joint.spring = read_spring(*s);
  out.where[body.name] = &t.table();
  out.bodies.push_back(body);
  out.joints.push_back(joint);
  read_state(t, out);
}

// N identical cylindrical links along their body z axes, joined end to end:
// link k hangs from the lower end of link k-1 (the first from `parent`).
void read_chain(const TomlView& t, ReadBodies& out) {
  t.check_keys({"name", "links", "parent", "joint_on_parent", "link_length", "radius", "mass", "density", "orientation",
                "angular_velocity", "spring"});
  const std::string prefix = t.required_string("name");
  const auto links = t.integer("links");
  if (!links) t.fail("links", "missing required field: the number of links (integer >= 1)");
  if (*links < 1 || *links > 3000) t.fail("links", "must be an integer from 1 to 3000");
  BodySpec link;
  link.solid = Solid::cylinder;
  link.length = positive(t, "link_length", "m");
  link.radius = t.has("radius") ? positive(t, "radius", "m") : link.length / 50.0;
  read_mass_or_density(t, link);
  JointSpring spring;
  if (auto s = t.subtable("spring")) spring = read_spring(*s);
  std::string parent = t.string("parent").value_or(kBaseName);
  for (long k = 1; k <= *links; ++k) {
    link.name = prefix + std::to_string(k);
    JointSpec joint;
    joint.child = link.name;
    joint.parent = parent;
    // The joint points move with the link lengths: (0, 0, +L/2) on the
    // link, (0, 0, -L/2) on the previous link.
    if (k == 1)
      joint.on_parent = read_joint_point(t, "joint_on_parent", "lower_end", joint.on_parent_follows_length);
    else
      joint.on_parent_follows_length = true;
    joint.on_child_follows_length = true;
    joint.spring = spring;
    out.where[link.name] = &t.table();
    out.bodies.push_back(link);
    out.joints.push_back(joint);
    read_state(t, out);
    parent = link.name;
  }
}

std::vector<Harmonic> read_harmonics(const TomlView& base, std::string_view axis) {
  std::vector<Harmonic> terms;
  for (const TomlView& h : base.table_array(axis)) {
    h.check_keys({"amplitude", "frequency", "phase", "unit"});
    Harmonic term;
    term.amplitude = h.required_number("amplitude");
    term.frequency = h.required_number("frequency");
    if (h.has("phase")) {
      const auto unit = h.string("unit");
      if (!unit || (*unit != "deg" && *unit != "rad")) h.fail("unit", "the phase needs unit = \"deg\" or \"rad\"");
      term.phase = h.required_number("phase") * (*unit == "deg" ? std::numbers::pi / 180.0 : 1.0);
    }
    terms.push_back(term);
  }
  return terms;
}

}  // namespace

namespace {

// A [[body]] or a [[chain]] table, where it stands in the file.
struct BodyEntry {
  int line, column;
  bool chain;
  const TomlView* view;
};

// The model's size, counted before any body is built: a tiny file of long
// chains must not make the reader build hundreds of thousands of bodies.
void require_supported_size(const std::vector<BodyEntry>& entries) {
  long long total = 0;
  for (const BodyEntry& e : entries) {
    const long long here = e.chain ? std::max<long long>(1, e.view->integer("links").value_or(1)) : 1;
    total += here;
    if (total <= kMaxBodies) continue;
    e.view->fail(e.chain ? "links" : "name",
                 "with this table the model has " + std::to_string(total) + " bodies; treedyn supports at most " +
                     std::to_string(kMaxBodies) +
                     " (at that size one right-hand side takes about 1.5 ms and the model 18 MiB, BENCHMARKS.md)");
  }
}

}  // namespace

ReadBodies read_bodies(const TomlView& root) {
  ReadBodies out;
  // Bodies in the job file's order, a [[chain]]'s links where its table
  // stands: that order is the user order of every output column.
  using Entry = BodyEntry;
  const std::vector<TomlView> bodies = root.table_array("body"), chains = root.table_array("chain");
  std::vector<Entry> entries;
  for (const TomlView& b : bodies) entries.push_back({line_of(b.table()), column_of(b.table()), false, &b});
  for (const TomlView& c : chains) entries.push_back({line_of(c.table()), column_of(c.table()), true, &c});
  std::stable_sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    return a.line != b.line ? a.line < b.line : a.column < b.column;
  });
  require_supported_size(entries);
  for (const Entry& e : entries) (e.chain ? read_chain : read_body)(*e.view, out);
  if (out.bodies.empty())
    throw JobError(root.file(), 0, 0, "body", "the job defines no bodies; add at least one [[body]] or [[chain]]");
  return out;
}

BaseMotionSpec read_base(const TomlView& t) {
  const std::string type = t.string("type").value_or("fixed");
  if (type == "fixed") {
    t.check_keys({"type", "position"});
    return FixedBase{t.vec3("position").value_or(Vec3::Zero())};
  }
  if (type == "constant_acceleration") {
    t.check_keys({"type", "position", "velocity", "acceleration"});
    return ConstantAccelerationBase{t.vec3("position").value_or(Vec3::Zero()),
                                    t.vec3("velocity").value_or(Vec3::Zero()),
                                    t.vec3("acceleration").value_or(Vec3::Zero())};
  }
  if (type == "harmonic") {
    t.check_keys({"type", "offset", "x", "y", "z"});
    HarmonicBase h;
    h.offset = t.vec3("offset").value_or(Vec3::Zero());
    h.axes = {read_harmonics(t, "x"), read_harmonics(t, "y"), read_harmonics(t, "z")};
    return h;
  }
  if (type == "tabulated") {
    t.check_keys({"type", "times", "positions"});
    TabulatedBase tab;
    const auto times = t.numbers("times");
    if (!times) t.fail("times", "missing required field: sample times in s");
    tab.times = *times;
    const toml::array* rows = t.table().get_as<toml::array>("positions");
    if (!rows) t.fail("positions", "missing required field: one [x, y, z] per time");
    for (const toml::node& row : *rows) {
      const toml::array* r = row.as_array();
      if (!r || r->size() != 3 || !(*r)[0].is_number() || !(*r)[1].is_number() || !(*r)[2].is_number())
        t.fail_at(&row, "positions", "each position must be [x, y, z] in m");
      tab.positions.emplace_back((*r)[0].value<double>().value(), (*r)[1].value<double>().value(),
                                 (*r)[2].value<double>().value());
    }
    return tab;  // sizes, order and finiteness: BaseMotion validates (reported at [base])
  }
  if (type == "sea_state") return read_sea_state(t);
  t.fail("type", "\"" + type +
                     "\" is not a base motion; allowed: \"fixed\", \"constant_acceleration\", "
                     "\"harmonic\", \"tabulated\", \"sea_state\"");
}

// The body a [[force]] or [[moment]] acts on must be one of the model's.
void require_body(const TomlView& t, const std::string& body, const ModelSpec& spec) {
  std::vector<std::string_view> names;
  for (const BodySpec& b : spec.bodies) {
    if (b.name == body) return;
    names.push_back(b.name);
  }
  t.fail("body", "'" + body + "' is not a body of the model" + did_you_mean(body, names));
}

void read_loads(const TomlView& root, ModelSpec& spec) {
  for (const TomlView& f : root.table_array("force")) {
    f.check_keys({"body", "point", "force"});
    PointForce pf;
    pf.body = f.required_string("body");
    require_body(f, pf.body, spec);
    pf.point = f.vec3("point").value_or(Vec3::Zero());
    const auto force = f.vec3("force");
    if (!force) f.fail("force", "missing required field: [Fx, Fy, Fz] in N, inertial frame");
    pf.force = *force;
    spec.forces.push_back(pf);
  }
  for (const TomlView& m : root.table_array("moment")) {
    m.check_keys({"body", "moment"});
    BodyMoment bm;
    bm.body = m.required_string("body");
    require_body(m, bm.body, spec);
    const auto moment = m.vec3("moment");
    if (!moment) m.fail("moment", "missing required field: [Mx, My, Mz] in N m, inertial frame");
    bm.moment = *moment;
    spec.moments.push_back(bm);
  }
}

}  // namespace treedyn
