// Conservation of energy and of the vertical angular momentum about the base
// point, for random trees of 1 to 10 bodies with a fixed base and no damping.
#include <gtest/gtest.h>

#include <random>

#include "dynamics/recovered.hpp"
#include "integrate/simulate.hpp"
#include "model/model.hpp"
#include "support/random_tree.hpp"

namespace treedyn {
namespace {

struct Drift {
  double energy = 0.0;    // max |E(t) - E(0)| / scale
  double momentum = 0.0;  // max |H_z(t) - H_z(0)| / scale
  IntegrationOutcome outcome;
};

Drift measure_drift(const ModelSpec& spec, const InitialState& initial, Parameterisation p, Method method,
                    double duration) {
  const Model model = build_model(spec);
  SimulationRequest request;
  request.parameterisation = p;
  request.settings.method = method;
  request.settings.relative_tolerance = 1e-12;
  request.settings.absolute_tolerance = 1e-12;
  for (int k = 0; k <= 200; ++k) request.output_times.push_back(duration * k / 200.0);
  std::vector<Energies> energy;
  std::vector<double> hz;
  Drift d;
  d.outcome = simulate(model, initial, request, [&](const Model& m, const Data& data) {
    const Recovered r = recover(m, data);
    energy.push_back(r.energy);
    hz.push_back(r.angular_momentum_about_base.z());
  });
  // Scales: energies can pass through zero, so compare with the energy that
  // is moving around (kinetic + |potential| + spring at the start).
  const double e_scale = energy[0].kinetic + std::abs(energy[0].potential) + energy[0].spring;
  double h_scale = 0.0;
  for (double h : hz) h_scale = std::max(h_scale, std::abs(h));
  h_scale = std::max(h_scale, 1e-3);
  for (std::size_t k = 0; k < energy.size(); ++k) {
    d.energy = std::max(d.energy, std::abs(energy[k].total() - energy[0].total()) / e_scale);
    d.momentum = std::max(d.momentum, std::abs(hz[k] - hz[0]) / h_scale);
  }
  return d;
}

TEST(Conservation, RandomTreesEnergyAndVerticalMomentum) {
  std::mt19937_64 rng(20261121);
  for (int n = 1; n <= 10; ++n) {
    testing::RandomTreeOptions options;
    options.bodies = n;
    const ModelSpec spec = testing::random_tree(rng, options);
    const InitialState state = testing::random_state(rng, n, 3.0);
    const Drift d = measure_drift(spec, state, Parameterisation::quaternion, Method::cvode_adams, 20.0);
    ASSERT_TRUE(d.outcome.ok()) << d.outcome.message;
    EXPECT_LT(d.energy, 1e-8) << "n = " << n;
    EXPECT_LT(d.momentum, 1e-8) << "n = " << n;
    std::printf("n=%2d  energy drift %.2e  H_z drift %.2e  steps %ld\n", n, d.energy, d.momentum,
                d.outcome.stats.steps);
  }
}

}  // namespace
}  // namespace treedyn
