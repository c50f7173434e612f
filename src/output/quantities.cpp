#include "output/quantities.hpp"

#include <array>
#include <stdexcept>

namespace treedyn {
namespace {

constexpr std::array<QuantityInfo, 14> kCatalogue{{
    {"orientation", "1",
     "orientation of each body as a unit quaternion (q0 scalar first), rotating body-frame "
     "components into the inertial frame"},
    {"angular_velocity", "rad/s", "absolute angular velocity of each body, inertial-frame components"},
    {"angular_acceleration", "rad/s^2",
     "absolute angular acceleration of each body, inertial-frame components"},
    {"com_position", "m", "position of each body's centre of mass, inertial frame"},
    {"com_velocity", "m/s", "velocity of each body's centre of mass, inertial frame"},
    {"com_acceleration", "m/s^2", "acceleration of each body's centre of mass, inertial frame"},
    {"joint_position", "m", "position of each body's inboard joint point, inertial frame"},
    {"joint_reaction", "N",
     "constraint force of each joint on its child body (the joint is named by its child), "
     "inertial frame"},
    {"joint_angle", "rad",
     "rotation angle of each joint: child relative to parent (to the inertial frame for the "
     "joint on the base), in [0, pi]"},
    {"joint_moment", "N m",
     "spring-damper moment of each joint on its child body, inertial frame"},
    {"energy", "J",
     "kinetic, potential (gravity and constant point forces), joint-spring and total energy"},
    {"angular_momentum", "kg m^2/s",
     "angular momentum of the whole tree about the base point, inertial frame"},
    {"base", "m, m/s, m/s^2", "base point position, velocity and acceleration r0, r0', r0''"},
    {"point_position", "m", "position of each requested body point ([[output.point]]), inertial frame"},
}};

void append(std::vector<double>& row, const Vec3& v) { row.insert(row.end(), {v.x(), v.y(), v.z()}); }

std::vector<std::string> per_body(const Model& model, std::initializer_list<const char*> suffixes) {
  std::vector<std::string> out;
  for (const BodySpec& b : model.spec.bodies)
    for (const char* s : suffixes) out.push_back(b.name + "." + s);
  return out;
}

}  // namespace

std::span<const QuantityInfo> quantity_catalogue() { return kCatalogue; }

const QuantityInfo* find_quantity(std::string_view name) {
  for (const QuantityInfo& q : kCatalogue)
    if (q.name == name) return &q;
  return nullptr;
}

std::vector<std::string> quantity_columns(std::string_view name, const Model& model,
                                          const OutputSpec& output) {
  if (name == "orientation") return per_body(model, {"q0", "q1", "q2", "q3"});
  if (name == "joint_angle") return per_body(model, {"angle"});
  if (name == "energy") return {"kinetic", "potential", "spring", "total"};
  if (name == "angular_momentum") return {"x", "y", "z"};
  if (name == "base")
    return {"position.x", "position.y", "position.z", "velocity.x", "velocity.y",
            "velocity.z", "acceleration.x", "acceleration.y", "acceleration.z"};
  if (name == "point_position") {
    std::vector<std::string> out;
    for (const OutputPoint& p : output.points)
      for (const char* s : {"x", "y", "z"}) out.push_back(p.name + "." + s);
    return out;
  }
  if (find_quantity(name)) return per_body(model, {"x", "y", "z"});
  throw std::invalid_argument("unknown quantity " + std::string(name));
}

void extract_quantity(std::string_view name, const Model&, const OutputSpec& output,
                      const Recovered& s, std::vector<double>& row) {
  const std::size_t n = s.rotation.size();
  auto each = [&](const std::vector<Vec3>& v) {
    for (const Vec3& x : v) append(row, x);
  };
  if (name == "orientation") {
    for (std::size_t i = 0; i < n; ++i) {
      Quat q(s.rotation[i]);
      if (q.w() < 0.0) q.coeffs() *= -1.0;  // one of q, -q: the one with q0 >= 0
      row.insert(row.end(), {q.w(), q.x(), q.y(), q.z()});
    }
  } else if (name == "angular_velocity") {
    each(s.angular_velocity);
  } else if (name == "angular_acceleration") {
    each(s.angular_acceleration);
  } else if (name == "com_position") {
    each(s.com_position);
  } else if (name == "com_velocity") {
    each(s.com_velocity);
  } else if (name == "com_acceleration") {
    each(s.com_acceleration);
  } else if (name == "joint_position") {
    each(s.joint_position);
  } else if (name == "joint_reaction") {
    each(s.joint_reaction);
  } else if (name == "joint_angle") {
    row.insert(row.end(), s.joint_angle.begin(), s.joint_angle.end());
  } else if (name == "joint_moment") {
    each(s.joint_moment);
  } else if (name == "energy") {
    row.insert(row.end(), {s.energy.kinetic, s.energy.potential, s.energy.spring, s.energy.total()});
  } else if (name == "angular_momentum") {
    append(row, s.angular_momentum_about_base);
  } else if (name == "base") {
    append(row, s.base.position);
    append(row, s.base.velocity);
    append(row, s.base.acceleration);
  } else if (name == "point_position") {
    for (const OutputPoint& p : output.points) append(row, body_point_position(s, p.body_index, p.point));
  } else {
    throw std::invalid_argument("unknown quantity " + std::string(name));
  }
}

}  // namespace treedyn
