// What a viewer needs to draw the tree moving (treedyn report's 3-D view,
// ParaView through the XDMF file): each body's shape and where its joint
// points sit, and, per output time, each body's pose and the stick figure's
// points. Written into every trajectory file as /motion.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "common/linalg.hpp"
#include "model/definition.hpp"
#include "model/model.hpp"
#include "output/output_spec.hpp"

namespace treedyn {

// The bodies in the user's order.
struct MotionScene {
  std::vector<std::string> body;
  std::vector<long long> parent;                   // user index of the parent; -1: the base
  std::vector<std::string> shape;                  // box, cylinder, sphere, none
  std::vector<double> dimensions;                  // n x 3: box edges; cylinder (r, r, length); sphere (r, r, r)
  std::vector<double> com_to_joint;                // n x 3: c_ii, CoM to inboard joint, body frame
  std::vector<std::array<long long, 2>> segments;  // the stick figure, into the points (below)
};

// Points per body u: 2u its inboard joint, 2u + 1 its CoM. Segments: every
// body's joint to its CoM, and every child's joint to its parent's CoM.
// Dimensions are the description's nominal ones.
MotionScene motion_scene(const ModelDefinition& definition, const Model& model);

// The quantities a Recorder records for /motion, in this order:
// com_position (3n), orientation (4n), joint_position (3n).
OutputSpec motion_output();

}  // namespace treedyn
