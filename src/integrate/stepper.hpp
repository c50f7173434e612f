// One SUNDIALS time stepper (CVODE or ARKODE ERKStep) driving a TreeOde, one
// step at a time so that the caller can change charts at a step's end (where
// the state is the integrator's own, not an interpolant). The callbacks never
// let an exception into SUNDIALS.
#pragma once

#include <sundials/sundials_config.h>

#include <memory>
#include <span>
#include <string>
#include <utility>

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
  // SUNDIALS' error messages come to message() instead of stderr: through
  // the context's handler stack (SUNDIALS 7), or the integrator's own
  // setter (SUNDIALS 6: CVodeSetErrHandlerFn, ERKStepSetErrHandlerFn).
  template <class LegacySetter>
  void capture_errors([[maybe_unused]] SUNContext context, [[maybe_unused]] void* memory,
                      [[maybe_unused]] LegacySetter legacy_setter, [[maybe_unused]] const char* setter_name) {
#if SUNDIALS_VERSION_MAJOR >= 7
    sundials::check(SUNContext_ClearErrHandlers(context), "SUNContext_ClearErrHandlers");
    sundials::check(SUNContext_PushErrHandler(context, record_error, this), "SUNContext_PushErrHandler");
#else
    sundials::check(legacy_setter(memory, record_error, this), setter_name);
#endif
  }

  FailureKind failure_ = FailureKind::none;
  std::string message_;  // written by the SUNDIALS error handler

 private:
#if SUNDIALS_VERSION_MAJOR >= 7
  static void record_error(int line, const char* function, const char* file, const char* message, SUNErrCode code,
                           void* stepper, SUNContext context);
#else
  static void record_error(int code, const char* module, const char* function, char* message, void* stepper);
#endif
};

// C callbacks shared by both steppers; user_data is the TreeOde.
int tree_rhs(double t, N_Vector y, N_Vector y_dot, void* ode);

// What both packages do alike, each through its own calls: the settings,
// the dense output, the time reached, and what a failure flag means.
struct PackageCalls {
  int (*set_tolerances)(void*, sunrealtype, sunrealtype);
  int (*set_user_data)(void*, void*);
  int (*set_max_num_steps)(void*, long);
  int (*set_max_step)(void*, sunrealtype);
  int (*set_init_step)(void*, sunrealtype);
  int (*get_dky)(void*, sunrealtype, int, N_Vector);
  int (*get_current_time)(void*, sunrealtype*);
  std::span<const std::pair<int, FailureKind>> failures;  // flag -> kind; others: FailureKind::other
  const char* package;                                    // named in set-up errors
};

// Tolerances, user data (the TreeOde), max_steps, max_step, initial_step.
void apply_settings(const PackageCalls& calls, void* memory, TreeOde& ode, const IntegratorSettings& settings);
void interpolate_with(const PackageCalls& calls, void* memory, double t, N_Vector y);
double current_time_of(const PackageCalls& calls, void* memory);
FailureKind classify(const PackageCalls& calls, int flag);

std::unique_ptr<Stepper> make_stepper(TreeOde& ode, const IntegratorSettings& settings, double t0, N_Vector y0,
                                      SUNContext context);

}  // namespace treedyn
