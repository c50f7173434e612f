// Cost of one right-hand-side evaluation of the tree ODE.
//
//   BM_Rhs/n/shape/solver              TreeOde::rhs with quaternions: unpack
//                                      the state, forward_dynamics, rates.
//   BM_ForwardDynamics/n/shape/solver  forward_dynamics alone on a filled Data.
//
// solver: 0 = recursive (section 8, the default), 1 = sparse_ldlt.
//
// Shapes: "chain" (body i hangs from body i-1) and "binary" (a balanced binary
// tree, p(i) = (i-1)/2 in 0-based regular order). Bodies have random masses,
// full random inertia tensors and joint points (fixed seed), gravity, a fixed
// base, no springs; the state has random orientations and angular velocities
// up to 3 rad/s. Times are per evaluation.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "dynamics/data.hpp"
#include "dynamics/pipeline.hpp"
#include "integrate/tree_ode.hpp"
#include "model/model.hpp"

namespace {

using namespace treedyn;

enum Shape : int { kChain = 0, kBinary = 1 };

Mat3 random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Quat q(normal(rng), normal(rng), normal(rng), normal(rng));
  return q.normalized().toRotationMatrix();
}

Vec3 random_direction(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  return Vec3(normal(rng), normal(rng), normal(rng)).normalized();
}

ModelSpec make_tree(int n, Shape shape) {
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

InitialState make_state(int n) {
  std::mt19937_64 rng(777 + static_cast<unsigned>(n));
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  InitialState s;
  for (int i = 0; i < n; ++i) {
    s.rotation.push_back(random_rotation(rng));
    s.angular_velocity.push_back(Vec3(u(rng), u(rng), u(rng)) * (3.0 / std::sqrt(3.0)));
  }
  return s;
}

AccelerationSolver solver_of(std::int64_t arg) {
  return arg == 0 ? AccelerationSolver::recursive : AccelerationSolver::sparse_ldlt;
}

std::string label_of(const benchmark::State& state) {
  return std::string(state.range(1) == kChain ? "chain" : "binary") + " " +
         std::string(name(solver_of(state.range(2))));
}

void BM_Rhs(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const Model model = build_model(make_tree(n, static_cast<Shape>(state.range(1))));
  TreeOde ode(model, Parameterisation::quaternion, solver_of(state.range(2)));
  std::vector<double> y(static_cast<std::size_t>(ode.size())), y_dot(y.size());
  ode.pack(make_state(n), y);
  if (!ode.rhs(0.0, y, y_dot)) {
    state.SkipWithError("rhs failed");
    return;
  }
  for (auto _ : state) {
    benchmark::DoNotOptimize(y.data());
    const bool ok = ode.rhs(0.0, y, y_dot);
    benchmark::DoNotOptimize(ok);
    benchmark::ClobberMemory();
  }
  state.SetLabel(label_of(state));
}

void BM_ForwardDynamics(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const Model model = build_model(make_tree(n, static_cast<Shape>(state.range(1))));
  Data data(model, solver_of(state.range(2)));
  const InitialState s = make_state(n);
  for (int i = 0; i < n; ++i) {
    data.rotation[i] = s.rotation[model.tree().user_index[i]];
    data.angular_velocity[i] = s.angular_velocity[model.tree().user_index[i]];
  }
  if (!forward_dynamics(model, data)) {
    state.SkipWithError("forward_dynamics failed");
    return;
  }
  for (auto _ : state) {
    benchmark::DoNotOptimize(data.rotation.data());
    const bool ok = forward_dynamics(model, data);
    benchmark::DoNotOptimize(ok);
    benchmark::ClobberMemory();
  }
  state.SetLabel(label_of(state));
}

void shapes_and_sizes(benchmark::internal::Benchmark* b) {
  b->ArgNames({"n", "shape", "solver"});
  for (int solver : {0, 1})
    for (int shape : {kChain, kBinary})
      for (int n : {1, 3, 10, 30, 100}) b->Args({n, shape, solver});
}

BENCHMARK(BM_Rhs)->Apply(shapes_and_sizes)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_ForwardDynamics)->Apply(shapes_and_sizes)->Unit(benchmark::kNanosecond);

}  // namespace

BENCHMARK_MAIN();
