#include "integrate/simulate.hpp"

#include <cmath>
#include <stdexcept>

#include "dynamics/pipeline.hpp"
#include "integrate/stepper.hpp"

namespace treedyn {

std::unique_ptr<Stepper> make_cvode_stepper(TreeOde&, const IntegratorSettings&, double, N_Vector,
                                            SUNContext);
std::unique_ptr<Stepper> make_erk_stepper(TreeOde&, const IntegratorSettings&, double, N_Vector,
                                          SUNContext);

std::unique_ptr<Stepper> make_stepper(TreeOde& ode, const IntegratorSettings& settings, double t0,
                                      N_Vector y0, SUNContext context) {
  switch (settings.method) {
    case Method::cvode_adams:
    case Method::cvode_bdf:
      return make_cvode_stepper(ode, settings, t0, y0, context);
    case Method::erk_dormand_prince:
    case Method::erk_verner:
      return make_erk_stepper(ode, settings, t0, y0, context);
  }
  throw std::invalid_argument("unknown integration method");
}

namespace {

void check_request(const Model& model, const InitialState& initial, const SimulationRequest& r) {
  const auto& s = r.settings;
  if (!(s.relative_tolerance > 0.0) || !(s.absolute_tolerance > 0.0))
    throw std::invalid_argument("integrator: tolerances must be positive");
  if (s.max_steps <= 0) throw std::invalid_argument("integrator: max_steps must be positive");
  if (static_cast<int>(initial.rotation.size()) != model.n ||
      static_cast<int>(initial.angular_velocity.size()) != model.n)
    throw std::invalid_argument("initial state: need one rotation and one angular velocity per body");
  double previous = r.start_time;
  for (double t : r.output_times) {
    if (!std::isfinite(t) || t < previous)
      throw std::invalid_argument("output times must be finite, non-decreasing and >= start time");
    previous = t;
  }
}

}  // namespace

IntegrationOutcome simulate(const Model& model, const InitialState& initial,
                            const SimulationRequest& request, const OutputObserver& observer) {
  check_request(model, initial, request);
  IntegrationOutcome outcome;
  outcome.time_reached = request.start_time;

  TreeOde ode(model, request.parameterisation, request.solver);
  sundials::Context context;
  sundials::Vector y(sundials::check_created(N_VNew_Serial(ode.size(), context), "N_VNew_Serial"));
  std::span<double> state{N_VGetArrayPointer(y.get()), static_cast<std::size_t>(ode.size())};
  ode.pack(initial, state);

  auto report = [&](double t) {
    ode.unpack(t, state);
    if (!forward_dynamics(model, ode.data())) return false;
    if (observer) observer(model, ode.data());
    return true;
  };

  std::unique_ptr<Stepper> stepper;
  try {
    stepper = make_stepper(ode, request.settings, request.start_time, y.get(), context);
  } catch (const sundials::SetupError& e) {
    outcome.failure = FailureKind::setup;
    outcome.message = e.what();
    return outcome;
  }

  std::vector<int> roots(static_cast<std::size_t>(ode.root_count()), 0);
  double t = request.start_time;
  for (double tout : request.output_times) {
    while (t < tout) {
      const AdvanceResult result = stepper->advance(tout, y.get(), t);
      if (result == AdvanceResult::failed) {
        add(outcome.stats, stepper->counters());
        outcome.failure = stepper->failure();
        outcome.message = stepper->message();
        outcome.time_reached = stepper->current_time();
        return outcome;
      }
      if (result == AdvanceResult::root) {
        // A chart is about to go bad: re-express and start afresh from here.
        stepper->root_flags(roots.data());
        outcome.stats.chart_changes += ode.recentre_charts(state, roots);
        add(outcome.stats, stepper->counters());
        stepper->restart(t, y.get());
        ++outcome.stats.restarts;
      }
    }
    // The output: at tout exactly (t == tout after a dense-output return).
    if (!report(tout)) {
      outcome.failure = FailureKind::nonfinite_state;
      outcome.message = "state is not finite at an output time";
      outcome.time_reached = tout;
      add(outcome.stats, stepper->counters());
      return outcome;
    }
    outcome.time_reached = tout;
  }
  add(outcome.stats, stepper->counters());
  return outcome;
}

}  // namespace treedyn
