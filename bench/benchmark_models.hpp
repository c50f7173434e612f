// The models and states every forward-dynamics benchmark uses, so that the
// solver benchmark and the peer comparison time the same trees.
//
// Shapes: "chain" (body i hangs from body i-1) and "binary" (a balanced binary
// tree, p(i) = (i-1)/2). Random masses 0.5-2 kg, full random inertia tensors
// (principal moments of an ellipsoid-like body, random axes), joint points
// 0.1-0.6 m from the CoM in random directions, gravity -9.81 z, a fixed base
// at the origin, no springs; states with random orientations and |w| up to
// 3 rad/s. Fixed seeds.
#pragma once

#include <cmath>
#include <random>
#include <string>

#include "model/initial_state.hpp"
#include "model/model.hpp"

namespace treedyn::bench {

enum Shape : int { kChain = 0, kBinary = 1 };

inline const char* shape_name(Shape s) { return s == kChain ? "chain" : "tree"; }

inline Mat3 random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Quat q(normal(rng), normal(rng), normal(rng), normal(rng));
  return q.normalized().toRotationMatrix();
}

inline Vec3 random_direction(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  return Vec3(normal(rng), normal(rng), normal(rng)).normalized();
}

inline ModelSpec make_tree(int n, Shape shape) {
  std::mt19937_64 rng(12345 + static_cast<unsigned>(n) * 2 + shape);
  std::uniform_real_distribution<double> mass(0.5, 2.0), moment(0.05, 0.4), len(0.1, 0.6);
  ModelSpec spec;
  auto name = [](int i) { return "b" + std::to_string(i); };
  for (int i = 0; i < n; ++i) {
    BodySpec b;
    b.name = name(i);
    b.mass = mass(rng);
    const double a = moment(rng), c = moment(rng), d = moment(rng);
    b.inertia = inertia_from_principal(Vec3(c + d, a + d, a + c), random_rotation(rng));
    spec.bodies.push_back(b);
    JointSpec j;
    j.child = b.name;
    if (i == 0) {
      j.parent = kBaseName;
    } else {
      j.parent = name(shape == kChain ? i - 1 : (i - 1) / 2);
      j.on_parent = random_direction(rng) * len(rng);
    }
    j.on_child = random_direction(rng) * len(rng);
    spec.joints.push_back(j);
  }
  return spec;
}

// User order (= the order of make_tree's bodies).
inline InitialState make_state(int n) {
  std::mt19937_64 rng(777 + static_cast<unsigned>(n));
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  InitialState s;
  for (int i = 0; i < n; ++i) {
    s.rotation.push_back(random_rotation(rng));
    s.angular_velocity.push_back(Vec3(u(rng), u(rng), u(rng)) * (3.0 / std::sqrt(3.0)));
  }
  return s;
}

}  // namespace treedyn::bench
