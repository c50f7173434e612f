// One SUNDIALS time stepper (CVODE or ARKODE ERKStep) driving a TreeOde, with
// chart-change roots. The callbacks never let an exception into SUNDIALS.
#pragma once

#include <memory>
#include <string>

#include "integrate/settings.hpp"
#include "integrate/sundials_handles.hpp"
#include "integrate/tree_ode.hpp"

namespace treedyn {

enum class AdvanceResult { reached, root, failed };

class Stepper {
 public:
  virtual ~Stepper() = default;
  // Integrates towards tout; on return y holds the state at t (tout through
  // the integrator's dense output, or the root, or where it failed).
  virtual AdvanceResult advance(double tout, N_Vector y, double& t) = 0;
  // Starts afresh from (t, y) after the state was re-expressed.
  virtual void restart(double t, N_Vector y) = 0;
  virtual void root_flags(int* flags) = 0;
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
int tree_roots(double t, N_Vector y, double* g, void* ode);

std::unique_ptr<Stepper> make_stepper(TreeOde& ode, const IntegratorSettings& settings,
                                      double t0, N_Vector y0, SUNContext context);

}  // namespace treedyn
