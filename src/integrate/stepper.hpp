// One SUNDIALS time stepper (CVODE or ARKODE ERKStep) driving a TreeOde, one
// step at a time so that the caller can change charts at a step's end (where
// the state is the integrator's own, not an interpolant). The callbacks never
// let an exception into SUNDIALS.
#pragma once

#include <memory>
#include <string>

#include "integrate/settings.hpp"
#include "integrate/sundials_handles.hpp"
#include "integrate/tree_ode.hpp"

namespace treedyn {

enum class AdvanceResult { stepped, failed };

class Stepper {
 public:
  virtual ~Stepper() = default;
  // One internal step towards tout (it may step past it); on return y holds
  // the state at the step's end t.
  virtual AdvanceResult step(double tout, N_Vector y, double& t) = 0;
  // The dense output of the last step at t inside it, into y. Throws
  // sundials::SetupError if SUNDIALS refuses.
  virtual void interpolate(double t, N_Vector y) = 0;
  // Starts afresh from (t, y) after the state was re-expressed. Throws
  // sundials::SetupError if SUNDIALS refuses.
  virtual void restart(double t, N_Vector y) = 0;
  // Counters since the last restart.
  virtual IntegratorStats counters() = 0;
  virtual double current_time() = 0;
  // Why the last advance failed.
  FailureKind failure() const { return failure_; }
  const std::string& message() const { return message_; }

 protected:
  FailureKind failure_ = FailureKind::none;
  std::string message_;  // written by the SUNDIALS error handler
  friend void record_sundials_error(int, const char*, const char*, char*, void*);
};

// SUNDIALS error handler: keeps the message for IntegrationOutcome instead of
// printing it.
void record_sundials_error(int code, const char* module, const char* function, char* msg,
                           void* stepper);

// C callbacks shared by both steppers; user_data is the TreeOde.
int tree_rhs(double t, N_Vector y, N_Vector y_dot, void* ode);

std::unique_ptr<Stepper> make_stepper(TreeOde& ode, const IntegratorSettings& settings,
                                      double t0, N_Vector y0, SUNContext context);

}  // namespace treedyn
