// Cost of one right-hand-side evaluation of the tree ODE.
//
//   BM_Rhs/n/shape/solver              TreeOde::rhs with quaternions: unpack
//                                      the state, forward_dynamics, rates.
//   BM_ForwardDynamics/n/shape/solver  forward_dynamics alone on a filled Data.
//
//   BM_BaseMotion/kind/components     BaseMotion::at, two axes of `components`
//                                      terms each: kind 0 = the same terms as a
//                                      HarmonicBase (a sincos per term), 1 = a
//                                      sea state (a complex recurrence).
//
// solver: 0 = recursive (docs/wittenburg.md, section 8, the default), 1 = sparse_ldlt.
//
// Models and states: benchmark_models.hpp. Times are per evaluation.
#include <benchmark/benchmark.h>
#include <malloc.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "benchmark_models.hpp"
#include "dynamics/data.hpp"
#include "dynamics/pipeline.hpp"
#include "integrate/tree_ode.hpp"
#include "model/model.hpp"

namespace {

using namespace treedyn;

using bench::kBinary;
using bench::kChain;
using bench::make_state;
using bench::Shape;

Model make_model(int n, Shape shape) { return build_model(bench::make_tree(n, shape)); }

AccelerationSolver solver_of(std::int64_t arg) {
  return arg == 0 ? AccelerationSolver::recursive : AccelerationSolver::sparse_ldlt;
}

std::string label_of(const benchmark::State& state) {
  return std::string(state.range(1) == kChain ? "chain" : "binary") + " " +
         std::string(name(solver_of(state.range(2))));
}

void BM_Rhs(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const Model model = make_model(n, static_cast<Shape>(state.range(1)));
  TreeOde ode(model, Parameterisation::quaternion, solver_of(state.range(2)));
  std::vector<double> y(static_cast<std::size_t>(ode.size())), y_dot(y.size());
  ode.pack(make_state(n), y);
  if (!ode.rhs(0.0, y, y_dot)) {
    state.SkipWithError("rhs failed");
    return;
  }
  for (auto _ : state) {
    benchmark::DoNotOptimize(y.data());
    bool ok = ode.rhs(0.0, y, y_dot);
    benchmark::DoNotOptimize(ok);
    benchmark::ClobberMemory();
  }
  state.SetLabel(label_of(state));
}

void BM_ForwardDynamics(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const Model model = make_model(n, static_cast<Shape>(state.range(1)));
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
    bool ok = forward_dynamics(model, data);
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

// The largest models (job/model_limits.hpp): a right-hand side's time and
// the heap the model and its ODE hold (counter MiB), for chains of 1,000,
// 10,000 and 100,000 bodies with the recursive solver.
void BM_RhsLarge(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const std::size_t before = mallinfo2().uordblks;
  const Model model = make_model(n, kChain);
  TreeOde ode(model, Parameterisation::quaternion, AccelerationSolver::recursive);
  std::vector<double> y(static_cast<std::size_t>(ode.size())), y_dot(y.size());
  state.counters["MiB"] = static_cast<double>(mallinfo2().uordblks - before) / 1048576.0;
  ode.pack(make_state(n), y);
  for (auto _ : state) {
    benchmark::DoNotOptimize(y.data());
    bool ok = ode.rhs(0.0, y, y_dot);
    benchmark::DoNotOptimize(ok);
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_RhsLarge)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ForwardDynamics)->Apply(shapes_and_sizes)->Unit(benchmark::kNanosecond);

// The base motion inside every right-hand side: a sea state of JONSWAP
// components on y and z (Hs 2 m, Tp 8 s), against the same terms written as
// a harmonic base. Measured side by side in one run.
void BM_BaseMotion(benchmark::State& state) {
  const bool sea_state = state.range(0) == 1;
  const int n = static_cast<int>(state.range(1));
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> phase(0.0, 6.283);
  SeaStateBase sea;
  HarmonicBase harmonic;
  for (int axis : {1, 2}) {
    SeaStateAxis a;
    a.significant_height = 2.0;
    a.peak_period = 8.0;
    a.min_frequency = 0.0625;
    a.max_frequency = 0.4375;
    for (int k = 0; k < n; ++k) a.phases.push_back(phase(rng));
    for (const SeaComponent& c : components(a)) harmonic.axes[axis].push_back({c.amplitude, c.frequency, c.phase});
    sea.axes[axis] = a;
  }
  const BaseMotion motion = sea_state ? BaseMotion(sea) : BaseMotion(harmonic);
  double t = 0.0;
  for (auto _ : state) {
    BaseKinematics k = motion.at(t);
    benchmark::DoNotOptimize(k);
    t += 1e-3;
  }
  state.SetLabel(sea_state ? "sea state" : "harmonic");
}
BENCHMARK(BM_BaseMotion)->ArgsProduct({{0, 1}, {64, 200}})->Unit(benchmark::kNanosecond);

}  // namespace

BENCHMARK_MAIN();
