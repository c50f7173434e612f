// What a run records: which quantities, and which body points.
#pragma once

#include <string>
#include <vector>

#include "common/linalg.hpp"

namespace treedyn {

// A point fixed in a body whose position is recorded (quantity "point_position").
struct OutputPoint {
  std::string name;
  std::string body;
  Vec3 point = Vec3::Zero();  // from the body's CoM, body frame, m
  int body_index = -1;        // user index of the body (set by the reader)
};

struct OutputSpec {
  std::vector<std::string> quantities;  // names from quantity_catalogue(), in the order written
  std::vector<OutputPoint> points;
};

}  // namespace treedyn
