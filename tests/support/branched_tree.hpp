// A branched 3-body tree under gravity (a trunk hung from the base carrying
// an arm and a bob), with its integrator and outputs: the model of the MPI
// ensemble tests; each test adds its own title and [ensemble].
#pragma once

#include <string>

namespace treedyn::testing {

inline const std::string kBranchedTreeModel = R"(
[environment]
gravity = [0.0, 0.0, -9.81]

[[body]]
name = "trunk"
shape = "cylinder"
radius = 0.02
length = 0.5
mass = 1.0
parent = "base"
joint_on_child = [0.0, 0.0, 0.25]
orientation = { type = "axis_angle", axis = [1, 0, 0], angle = 30, unit = "deg" }

[[body]]
name = "arm"
shape = "cylinder"
radius = 0.02
length = 0.4
mass = 0.5
parent = "trunk"
joint_on_parent = [0.0, 0.0, -0.25]
joint_on_child = [0.0, 0.0, 0.2]
angular_velocity = { value = [0.0, 0.0, 2.0], frame = "inertial", unit = "rad/s" }

[[body]]
name = "bob"
shape = "sphere"
radius = 0.05
mass = 0.3
parent = "trunk"
joint_on_parent = [0.05, 0.0, -0.25]
joint_on_child = [0.0, 0.0, 0.05]

[integrator]
method = "cvode_adams"
rtol = 1e-8
atol = 1e-10

[output]
end_time = 2.0
step = 0.05
quantities = ["energy", "com_position", "angular_velocity", "joint_angle"]

)";

}  // namespace treedyn::testing
