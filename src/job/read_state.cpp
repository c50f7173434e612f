// Initial orientations and angular velocities.
#include <cmath>
#include <numbers>

#include "job/readers.hpp"

namespace treedyn {
namespace {

double angle_scale(const TomlView& t) {
  const auto unit = t.string("unit");
  if (!unit) t.fail("unit", "missing; angles need an explicit unit: \"deg\" or \"rad\"");
  if (*unit == "deg") return std::numbers::pi / 180.0;
  if (*unit == "rad") return 1.0;
  t.fail("unit", "\"" + *unit + "\" is not an angle unit; allowed: \"deg\" or \"rad\"");
}

Vec3 angles(const TomlView& t) {
  const auto a = t.vec3("angles");
  if (!a) t.fail("angles", "missing required field: three angles [a, b, c]");
  return *a * angle_scale(t);
}

}  // namespace

Mat3 read_orientation(const TomlView& t) {
  const std::string type = t.required_string("type");
  if (type == "quaternion") {
    t.check_keys({"type", "q"});
    const auto q = t.numbers("q");
    if (!q || q->size() != 4) t.fail("q", "expected 4 numbers [q0, q1, q2, q3], scalar first");
    const Quat quat((*q)[0], (*q)[1], (*q)[2], (*q)[3]);
    if (quat.norm() < 1e-12) t.fail("q", "a zero quaternion is not a rotation");
    return quat.normalized().toRotationMatrix();
  }
  if (type == "axis_angle") {
    t.check_keys({"type", "axis", "angle", "unit"});
    const auto axis = t.vec3("axis");
    if (!axis) t.fail("axis", "missing required field: the rotation axis [x, y, z]");
    if (axis->norm() < 1e-12) t.fail("axis", "the axis must not be the zero vector");
    const double angle = t.required_number("angle") * angle_scale(t);
    return Eigen::AngleAxisd(angle, axis->normalized()).toRotationMatrix();
  }
  if (type == "euler313") {
    t.check_keys({"type", "angles", "unit"});
    const Vec3 a = angles(t);  // psi, theta, phi
    return (Eigen::AngleAxisd(a[0], Vec3::UnitZ()) * Eigen::AngleAxisd(a[1], Vec3::UnitX()) *
            Eigen::AngleAxisd(a[2], Vec3::UnitZ()))
        .toRotationMatrix();
  }
  if (type == "bryant123") {
    t.check_keys({"type", "angles", "unit"});
    const Vec3 a = angles(t);
    return (Eigen::AngleAxisd(a[0], Vec3::UnitX()) * Eigen::AngleAxisd(a[1], Vec3::UnitY()) *
            Eigen::AngleAxisd(a[2], Vec3::UnitZ()))
        .toRotationMatrix();
  }
  t.fail("type", "\"" + type +
                     "\" is not an orientation type; allowed: \"quaternion\", \"axis_angle\", "
                     "\"euler313\", \"bryant123\"");
}

AngularVelocityInput read_angular_velocity(const TomlView& t, const Mat3& orientation) {
  t.check_keys({"value", "frame", "unit"});
  const auto value = t.vec3("value");
  if (!value) t.fail("value", "missing required field: [wx, wy, wz]");
  double scale = 1.0;
  const std::string unit = t.string("unit").value_or("rad/s");
  if (unit == "deg/s")
    scale = std::numbers::pi / 180.0;
  else if (unit != "rad/s")
    t.fail("unit", "\"" + unit + "\" is not allowed; use \"rad/s\" or \"deg/s\"");
  const auto frame = t.string("frame");
  if (!frame) t.fail("frame", "missing; say in which frame the components are: \"inertial\" or \"body\"");
  if (*frame == "inertial") return {*value * scale, std::nullopt};
  if (*frame == "body") return {orientation * (*value * scale), *value * scale};
  t.fail("frame", "\"" + *frame + "\" is not allowed; use \"inertial\" or \"body\"");
}

}  // namespace treedyn
