#include "integrate/simulate.hpp"

#include "common/format.hpp"

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

std::string failure_reason(const IntegrationOutcome& outcome) {
  return std::string(name(outcome.failure)) + " at t = " + format_number(outcome.time_reached) + " s" +
         (outcome.message.empty() ? "" : ": " + outcome.message);
}

IntegrationOutcome simulate(const Model& model, const InitialState& initial,
                            const SimulationRequest& request, const OutputObserver& observer) {
  check_request(model, initial, request);
  IntegrationOutcome outcome;
  outcome.time_reached = request.start_time;

  TreeOde ode(model, request.parameterisation, request.solver);
  sundials::Context context;
  sundials::Vector y(sundials::check_created(N_VNew_Serial(ode.size(), context), "N_VNew_Serial"));
  sundials::Vector y_out(sundials::check_created(N_VNew_Serial(ode.size(), context), "N_VNew_Serial"));
  auto view = [&](N_Vector v) {
    return std::span<double>{N_VGetArrayPointer(v), static_cast<std::size_t>(ode.size())};
  };
  const std::span<double> state = view(y.get());
  ode.pack(initial, state);

  std::unique_ptr<Stepper> stepper;
  auto fail = [&](FailureKind kind, std::string message, double time) {
    if (stepper) add(outcome.stats, stepper->counters());
    outcome.failure = kind;
    outcome.message = std::move(message);
    outcome.time_reached = time;
    return outcome;
  };
  try {
    stepper = make_stepper(ode, request.settings, request.start_time, y.get(), context);
  } catch (const sundials::SetupError& e) {
    return fail(FailureKind::setup, e.what(), request.start_time);
  }

  const std::vector<double>& outputs = request.output_times;
  std::size_t next = 0;
  std::vector<double> margins(static_cast<std::size_t>(ode.root_count()));
  std::vector<int> change(margins.size(), 0);
  long steps_since_output = 0;
  double t = request.start_time;
  try {
    // Every output time up to t: the step's end itself, or its dense output.
    auto report_up_to = [&](double t_end) {
      for (; next < outputs.size() && outputs[next] <= t_end; ++next) {
        const double tout = outputs[next];
        N_Vector at = y.get();
        if (tout < t_end) {
          stepper->interpolate(tout, y_out.get());
          at = y_out.get();
        }
        ode.unpack(tout, view(at));
        if (!forward_dynamics(model, ode.data())) return false;
        if (observer) observer(model, ode.data());
        outcome.time_reached = tout;
        steps_since_output = 0;
      }
      return true;
    };
    if (!report_up_to(t)) return fail(FailureKind::nonfinite_state, "state is not finite at an output time", t);
    while (next < outputs.size()) {
      if (stepper->step(outputs[next], y.get(), t) == AdvanceResult::failed)
        return fail(stepper->failure(), stepper->message(), stepper->current_time());
      if (!report_up_to(t))
        return fail(FailureKind::nonfinite_state, "state is not finite at an output time", outputs[next]);
      if (next == outputs.size()) break;
      if (++steps_since_output >= request.settings.max_steps)
        return fail(FailureKind::too_much_work,
                    "at t = " + std::to_string(t) + " s: " + std::to_string(request.settings.max_steps) +
                        " steps (max_steps) taken before the next output time",
                    t);
      // A chart past its margin is changed here, at the step's end, where the
      // state is the integrator's own: the restart adds no interpolation
      // error. The switch instant is free inside the margin.
      ode.chart_margins(state, margins);
      ++outcome.stats.root_evaluations;
      bool any = false;
      for (std::size_t i = 0; i < margins.size(); ++i) {
        change[i] = margins[i] < 0.0 ? 1 : 0;
        any = any || change[i] != 0;
      }
      if (!any) continue;
      outcome.stats.chart_changes += ode.recentre_charts(state, change);
      for (std::size_t i = 0; i < change.size(); ++i)
        if (change[i] != 0) outcome.chart_changes.push_back({t, model.tree().user_index[i]});
      add(outcome.stats, stepper->counters());
      stepper->restart(t, y.get());
      ++outcome.stats.restarts;
    }
  } catch (const sundials::SetupError& e) {
    return fail(FailureKind::setup, e.what(), t);
  }
  add(outcome.stats, stepper->counters());
  return outcome;
}

}  // namespace treedyn
