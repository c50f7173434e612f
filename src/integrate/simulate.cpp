#include "integrate/simulate.hpp"

#include <cmath>
#include <stdexcept>

#include "common/format.hpp"
#include "dynamics/pipeline.hpp"
#include "integrate/state_vector.hpp"
#include "integrate/stepper.hpp"

namespace treedyn {

std::unique_ptr<Stepper> make_cvode_stepper(TreeOde&, const IntegratorSettings&, double, N_Vector, SUNContext);
std::unique_ptr<Stepper> make_erk_stepper(TreeOde&, const IntegratorSettings&, double, N_Vector, SUNContext);

std::unique_ptr<Stepper> make_stepper(TreeOde& ode, const IntegratorSettings& settings, double t0, N_Vector y0,
                                      SUNContext context) {
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

namespace {

// One integration in progress: the ODE, SUNDIALS' vectors and stepper, the
// next output time, and the outcome so far. simulate() drives it step by
// step; each method is one stage of a step.
class Integration {
 public:
  Integration(const Model& model, const InitialState& initial, const SimulationRequest& request,
              const OutputObserver& observer)
      : model_(model),
        request_(request),
        observer_(observer),
        ode_(model, request.parameterisation, request.solver),
        y_(sundials::new_state_vector(ode_.size(), context_)),
        y_out_(sundials::new_state_vector(ode_.size(), context_)),
        margins_(static_cast<std::size_t>(ode_.charts())),
        change_(margins_.size(), 0) {
    outcome_.time_reached = request.start_time;
    ode_.pack(initial, view(y_.get()));
  }

  IntegrationOutcome run() {
    try {
      stepper_ = make_stepper(ode_, request_.settings, request_.start_time, y_.get(), context_);
    } catch (const sundials::SetupError& e) {
      return fail(FailureKind::setup, e.what(), request_.start_time);
    }
    try {
      if (!report_up_to(t_)) return fail(FailureKind::nonfinite_state, "state is not finite at an output time", t_);
      while (next_ < outputs().size()) {
        if (stepper_->step(outputs()[next_], y_.get(), t_) == AdvanceResult::failed)
          return fail(stepper_->failure(), stepper_->message(), stepper_->current_time());
        if (!report_up_to(t_))
          return fail(FailureKind::nonfinite_state, "state is not finite at an output time", outputs()[next_]);
        if (next_ == outputs().size()) break;
        if (++steps_since_output_ >= request_.settings.max_steps)
          return fail(FailureKind::too_much_work,
                      "at t = " + std::to_string(t_) + " s: " + std::to_string(request_.settings.max_steps) +
                          " steps (max_steps) taken before the next output time",
                      t_);
        change_charts();
      }
    } catch (const sundials::SetupError& e) {
      return fail(FailureKind::setup, e.what(), t_);
    }
    add(outcome_.stats, stepper_->counters());
    return outcome_;
  }

 private:
  const std::vector<double>& outputs() const { return request_.output_times; }
  std::span<double> view(N_Vector v) {
    return std::span<double>{N_VGetArrayPointer(v), static_cast<std::size_t>(ode_.size())};
  }

  IntegrationOutcome fail(FailureKind kind, std::string message, double time) {
    if (stepper_) add(outcome_.stats, stepper_->counters());
    outcome_.failure = kind;
    outcome_.message = std::move(message);
    outcome_.time_reached = time;
    return outcome_;
  }

  // Every output time up to t_end: the step's end itself, or its dense output.
  bool report_up_to(double t_end) {
    for (; next_ < outputs().size() && outputs()[next_] <= t_end; ++next_) {
      const double tout = outputs()[next_];
      N_Vector at = y_.get();
      if (tout < t_end) {
        stepper_->interpolate(tout, y_out_.get());
        at = y_out_.get();
      }
      ode_.unpack(tout, view(at));
      if (!request_.accelerations_at_outputs)
        compute_kinematics_and_loads(model_, ode_.data());
      else if (!forward_dynamics(model_, ode_.data()))
        return false;
      if (observer_) observer_(model_, ode_.data());
      outcome_.time_reached = tout;
      steps_since_output_ = 0;
    }
    return true;
  }

  // A chart past its margin is changed here, at the step's end, where the
  // state is the integrator's own: the restart adds no interpolation error.
  // The switch instant is free inside the margin.
  void change_charts() {
    const std::span<double> state = view(y_.get());
    ode_.chart_margins(state, margins_);
    ++outcome_.stats.chart_checks;
    bool any = false;
    for (std::size_t i = 0; i < margins_.size(); ++i) {
      change_[i] = margins_[i] < 0.0 ? 1 : 0;
      any = any || change_[i] != 0;
    }
    if (!any) return;
    outcome_.stats.chart_changes += ode_.recentre_charts(state, change_);
    for (std::size_t i = 0; i < change_.size(); ++i)
      if (change_[i] != 0) outcome_.chart_changes.push_back({t_, model_.tree().user_index[i]});
    add(outcome_.stats, stepper_->counters());
    stepper_->restart(t_, y_.get());
    ++outcome_.stats.restarts;
  }

  const Model& model_;
  const SimulationRequest& request_;
  const OutputObserver& observer_;
  TreeOde ode_;
  sundials::Context context_;
  sundials::Vector y_, y_out_;
  std::unique_ptr<Stepper> stepper_;
  std::vector<double> margins_;
  std::vector<int> change_;
  IntegrationOutcome outcome_;
  std::size_t next_ = 0;  // the next output time
  long steps_since_output_ = 0;
  double t_ = request_.start_time;
};

}  // namespace

IntegrationOutcome simulate(const Model& model, const InitialState& initial, const SimulationRequest& request,
                            const OutputObserver& observer) {
  check_request(model, initial, request);
  return Integration(model, initial, request, observer).run();
}

}  // namespace treedyn
