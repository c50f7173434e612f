// Random trees and states for property tests: every test that draws one uses
// a fixed seed, so a failure reproduces.
#pragma once

#include <random>
#include <vector>

#include "model/initial_state.hpp"
#include "model/model_spec.hpp"

namespace treedyn::testing {

struct RandomTreeOptions {
  int bodies = 3;
  bool chain = false;             // each body hangs from the previous one
  bool star = false;              // every other body hangs from the first
  bool shuffle_order = true;      // list bodies in a random (non-regular) order
  double spring_stiffness = 0.0;  // isotropic joint stiffness scale, 0: none
  double spring_damping = 0.0;    // isotropic joint damping scale, 0: none
};

// Random masses (0.5-2 kg), random full inertia tensors obeying the triangle
// inequality, random joint points (0.1-0.6 m), gravity -9.81 z, fixed base.
ModelSpec random_tree(std::mt19937_64& rng, const RandomTreeOptions& options);

Mat3 random_rotation(std::mt19937_64& rng);
Vec3 random_vector(std::mt19937_64& rng, double scale);

// Random orientations and angular velocities (|w| up to `spin` rad/s), user order.
InitialState random_state(std::mt19937_64& rng, int bodies, double spin);

// Rotation angle of A^T B, radians.
double rotation_distance(const Mat3& A, const Mat3& B);

}  // namespace treedyn::testing
