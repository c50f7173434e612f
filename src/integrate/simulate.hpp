// Integrates one trajectory of a tree and reports at requested output times.
#pragma once

#include <functional>
#include <span>

#include "dynamics/data.hpp"
#include "integrate/settings.hpp"
#include "integrate/tree_ode.hpp"
#include "kinematics/parameterisation.hpp"
#include "model/initial_state.hpp"
#include "model/model.hpp"

namespace treedyn {

// Called at every output time with data holding the state there and the
// forward dynamics already run on it (pass both to recover()); only its
// kinematics and loads when the request's accelerations_at_outputs is false.
using OutputObserver = std::function<void(const Model& model, const Data& data)>;

// How to integrate: from when, to which output times, in which coordinates,
// with which method. What to integrate is a Model and an InitialState.
struct SimulationRequest {
  double start_time = 0.0;
  std::vector<double> output_times;  // non-decreasing, >= start_time
  Parameterisation parameterisation = Parameterisation::quaternion;
  AccelerationSolver solver = AccelerationSolver::automatic;  // [integrator] solver
  IntegratorSettings settings;
  // Whether the observer needs accelerations (forward_dynamics) at every
  // output time; without them an output costs a fraction of a right-hand
  // side (compute_kinematics_and_loads). A Recorder says which it needs.
  bool accelerations_at_outputs = true;
};

// Never throws for integration trouble: a failure comes back in the outcome
// with the time reached. Throws std::invalid_argument for a malformed request
// (wrong sizes, decreasing output times, non-positive tolerances).
// Why an integration failed, in one line: "too_much_work at t = 1.5 s: ...".
// The ensemble's /samples/reason and a rerun sample's /sample reason.
std::string failure_reason(const IntegrationOutcome& outcome);

IntegrationOutcome simulate(const Model& model, const InitialState& initial, const SimulationRequest& request,
                            const OutputObserver& observer);

}  // namespace treedyn
