#include "support/random_tree.hpp"

#include <algorithm>
#include <numeric>
#include <string>

namespace treedyn::testing {

Mat3 random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Quat q(normal(rng), normal(rng), normal(rng), normal(rng));
  return q.normalized().toRotationMatrix();
}

Vec3 random_vector(std::mt19937_64& rng, double scale) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return scale * Vec3(u(rng), u(rng), u(rng));
}

ModelSpec random_tree(std::mt19937_64& rng, const RandomTreeOptions& options) {
  std::uniform_real_distribution<double> mass(0.5, 2.0), moment(0.05, 0.4), len(0.1, 0.6), unit(0.0, 1.0);
  const int n = options.bodies;
  ModelSpec spec;
  std::vector<int> parent(n, -1);
  for (int i = 1; i < n; ++i)
    parent[i] = options.chain ? i - 1 : options.star ? 0 : std::uniform_int_distribution<int>(0, i - 1)(rng);
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  if (options.shuffle_order) std::shuffle(order.begin(), order.end(), rng);
  auto body_name = [](int i) { return "b" + std::to_string(i); };
  for (int k : order) {
    BodySpec b;
    b.name = body_name(k);
    b.mass = mass(rng);
    // Principal moments from a random ellipsoid-like body: triangle inequality holds.
    const double a = moment(rng), c = moment(rng), d = moment(rng);
    const Vec3 principal(c + d, a + d, a + c);
    b.inertia = inertia_from_principal(principal, random_rotation(rng));
    spec.bodies.push_back(b);
  }
  for (int k : order) {
    JointSpec j;
    j.child = body_name(k);
    j.parent = parent[k] < 0 ? kBaseName : body_name(parent[k]);
    j.on_child = random_vector(rng, 1.0).normalized() * len(rng);
    j.on_parent = parent[k] < 0 ? Vec3::Zero() : Vec3(random_vector(rng, 1.0).normalized() * len(rng));
    if (options.spring_stiffness > 0.0)
      j.spring.stiffness = options.spring_stiffness * (0.5 + unit(rng)) * Mat3::Identity();
    if (options.spring_damping > 0.0) j.spring.damping = options.spring_damping * (0.5 + unit(rng)) * Mat3::Identity();
    spec.joints.push_back(j);
  }
  return spec;
}

InitialState random_state(std::mt19937_64& rng, int bodies, double spin) {
  InitialState s;
  for (int i = 0; i < bodies; ++i) {
    s.rotation.push_back(random_rotation(rng));
    s.angular_velocity.push_back(random_vector(rng, spin / std::sqrt(3.0)));
  }
  return s;
}

double rotation_distance(const Mat3& A, const Mat3& B) { return Eigen::AngleAxisd(Mat3(A.transpose() * B)).angle(); }

}  // namespace treedyn::testing
