#include "output/quantities.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace treedyn {
namespace {

// Writes v's components at `out` and returns the place after them.
double* put(double* out, const Vec3& v) {
  out[0] = v.x();
  out[1] = v.y();
  out[2] = v.z();
  return out + 3;
}

double* put_each(double* out, const std::vector<Vec3>& values) {
  for (const Vec3& v : values) out = put(out, v);
  return out;
}

std::vector<std::string> per_body(const Model& model, std::initializer_list<const char*> suffixes) {
  std::vector<std::string> out;
  for (int u = 0; u < model.n; ++u)
    for (const char* s : suffixes) out.push_back(model.tree().user_body_name(u) + "." + s);
  return out;
}

std::vector<std::string> body_xyz(const Model& m, const OutputSpec&) { return per_body(m, {"x", "y", "z"}); }

// A per-body vector quantity: one member of Recovered.
template <std::vector<Vec3> Recovered::*member>
double* body_vectors(const Recovered& s, const OutputSpec&, double* out) {
  return put_each(out, s.*member);
}

constexpr std::array<QuantityInfo, 17> kCatalogue{{
    {"orientation", "1",
     "orientation of each body as a unit quaternion (q0 scalar first, q0 >= 0), rotating "
     "body-frame components into the inertial frame",
     [](const Model& m, const OutputSpec&) {
       return per_body(m, {"q0", "q1", "q2", "q3"});
     },
     [](const Recovered& s, const OutputSpec&, double* out) {
       for (const Mat3& A : s.rotation) {
         const Quat q = canonical_quaternion(A);
         *out++ = q.w();
         out = put(out, q.vec());
       }
       return out;
     }},
    {"angular_velocity", "rad/s", "absolute angular velocity of each body, inertial-frame components", body_xyz,
     body_vectors<&Recovered::angular_velocity>},
    {"angular_acceleration", "rad/s^2", "absolute angular acceleration of each body, inertial-frame components",
     body_xyz, body_vectors<&Recovered::angular_acceleration>, kRecoverAccelerations},
    {"com_position", "m", "position of each body's centre of mass, inertial frame", body_xyz,
     body_vectors<&Recovered::com_position>},
    {"com_velocity", "m/s", "velocity of each body's centre of mass, inertial frame", body_xyz,
     body_vectors<&Recovered::com_velocity>},
    {"com_acceleration", "m/s^2", "acceleration of each body's centre of mass, inertial frame", body_xyz,
     body_vectors<&Recovered::com_acceleration>, kRecoverAccelerations},
    {"com_offset", "m",
     "each body's centre of mass from the base point, r_i - r0, inertial frame, and its horizontal length "
     "sqrt(x^2 + y^2) (horizontal for gravity along z): how far a payload swings out from the point it "
     "hangs from",
     [](const Model& m, const OutputSpec&) {
       return per_body(m, {"x", "y", "z", "horizontal"});
     },
     [](const Recovered& s, const OutputSpec&, double* out) {
       for (const Vec3& r : s.com_position) {
         const Vec3 d = r - s.base.position;
         out = put(out, d);
         *out++ = std::hypot(d.x(), d.y());
       }
       return out;
     }},
    {"joint_position", "m", "position of each body's inboard joint point, inertial frame", body_xyz,
     body_vectors<&Recovered::joint_position>},
    {"joint_reaction", "N",
     "constraint force of each joint on its child body (the joint is named by its child), "
     "inertial frame",
     body_xyz, body_vectors<&Recovered::joint_reaction>, kRecoverAccelerations},
    {"joint_reaction_magnitude", "N",
     "magnitude of each joint's constraint force (joint_reaction): a cable's or link's tension "
     "at its upper joint",
     [](const Model& m, const OutputSpec&) { return per_body(m, {"magnitude"}); },
     [](const Recovered& s, const OutputSpec&, double* out) {
       for (const Vec3& f : s.joint_reaction) *out++ = f.norm();
       return out;
     },
     kRecoverAccelerations},
    {"joint_angle", "rad",
     "rotation angle of each joint: child relative to parent (to the inertial frame for the "
     "joint on the base), in [0, pi]",
     [](const Model& m, const OutputSpec&) { return per_body(m, {"angle"}); },
     [](const Recovered& s, const OutputSpec&, double* out) {
       return std::copy(s.joint_angle.begin(), s.joint_angle.end(), out);
     },
     kRecoverJointAngles},
    {"joint_axis", "1",
     "unit axis of each joint's relative rotation (see joint_angle), parent-frame components; "
     "zero when the angle is zero",
     body_xyz, body_vectors<&Recovered::joint_axis>, kRecoverJointAngles},
    {"joint_moment", "N m", "spring-damper moment of each joint on its child body, inertial frame", body_xyz,
     body_vectors<&Recovered::joint_moment>},
    {"energy", "J", "kinetic, potential (gravity and constant point forces), joint-spring and total energy",
     [](const Model&, const OutputSpec&) {
       return std::vector<std::string>{"kinetic", "potential", "spring", "total"};
     },
     [](const Recovered& s, const OutputSpec&, double* out) {
       out[0] = s.energy.kinetic;
       out[1] = s.energy.potential;
       out[2] = s.energy.spring;
       out[3] = s.energy.total();
       return out + 4;
     },
     kRecoverEnergy},
    {"angular_momentum", "kg m^2/s", "angular momentum of the whole tree about the base point, inertial frame",
     [](const Model&, const OutputSpec&) {
       return std::vector<std::string>{"x", "y", "z"};
     },
     [](const Recovered& s, const OutputSpec&, double* out) { return put(out, s.angular_momentum_about_base); },
     kRecoverAngularMomentum},
    {"base", "m, m/s, m/s^2", "base point position, velocity and acceleration r0, r0', r0''",
     [](const Model&, const OutputSpec&) {
       return std::vector<std::string>{"position.x", "position.y",     "position.z",     "velocity.x",    "velocity.y",
                                       "velocity.z", "acceleration.x", "acceleration.y", "acceleration.z"};
     },
     [](const Recovered& s, const OutputSpec&, double* out) {
       return put(put(put(out, s.base.position), s.base.velocity), s.base.acceleration);
     }},
    {"point_position", "m", "position of each requested body point ([[output.point]]), inertial frame",
     [](const Model&, const OutputSpec& output) {
       std::vector<std::string> out;
       for (const OutputPoint& p : output.points)
         for (const char* s : {"x", "y", "z"}) out.push_back(p.name + "." + s);
       return out;
     },
     [](const Recovered& s, const OutputSpec& output, double* out) {
       for (const OutputPoint& p : output.points) out = put(out, body_point_position(s, p.body_index, p.point));
       return out;
     }},
}};

}  // namespace

std::span<const QuantityInfo> quantity_catalogue() { return kCatalogue; }

const QuantityInfo* find_quantity(std::string_view name) {
  for (const QuantityInfo& q : kCatalogue)
    if (q.name == name) return &q;
  return nullptr;
}

ColumnLayout column_layout(const Model& model, const OutputSpec& output) {
  ColumnLayout l;
  for (const std::string& q : output.quantities) {
    const QuantityInfo* info = find_quantity(q);
    if (!info) throw std::invalid_argument("unknown quantity " + q);
    l.quantity.push_back(q);
    l.info.push_back(info);
    l.offset.push_back(l.columns);
    l.names.push_back(info->columns(model, output));
    l.needs |= info->needs;
    l.columns += l.names.back().size();
  }
  return l;
}

std::string column_unit(const ColumnLayout& layout, std::size_t quantity, std::size_t column) {
  const std::string_view all = layout.info[quantity]->units;
  std::vector<std::string> units;
  for (std::size_t start = 0;;) {
    const std::size_t comma = all.find(", ", start);
    units.emplace_back(all.substr(start, comma == std::string_view::npos ? all.npos : comma - start));
    if (comma == std::string_view::npos) break;
    start = comma + 2;
  }
  const std::size_t columns = layout.names[quantity].size();
  if (units.size() == 1 || columns % units.size() != 0) return std::string(all);
  return units[column / (columns / units.size())];
}

}  // namespace treedyn
