// CVODE: Adams with fixed-point iteration (non-stiff) or BDF with Newton and a
// dense difference-quotient Jacobian.
#include <cvode/cvode.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <vector>

#include "integrate/stepper.hpp"

namespace treedyn {
namespace {

using sundials::check;
using sundials::check_created;

FailureKind classify(int flag) {
  switch (flag) {
    case CV_TOO_MUCH_WORK:
      return FailureKind::too_much_work;
    case CV_TOO_MUCH_ACC:
      return FailureKind::too_much_accuracy;
    case CV_ERR_FAILURE:
      return FailureKind::error_test_failures;
    case CV_CONV_FAILURE:
    case CV_LSETUP_FAIL:
    case CV_LSOLVE_FAIL:
    case CV_NLS_FAIL:
      return FailureKind::convergence_failures;
    case CV_RHSFUNC_FAIL:
    case CV_REPTD_RHSFUNC_ERR:
    case CV_UNREC_RHSFUNC_ERR:
    case CV_FIRST_RHSFUNC_ERR:
      return FailureKind::nonfinite_state;
    default:
      return FailureKind::other;
  }
}

class CvodeStepper final : public Stepper {
 public:
  CvodeStepper(TreeOde& ode, const IntegratorSettings& s, double t0, N_Vector y0, SUNContext ctx)
      : ode_(ode) {
    const bool bdf = s.method == Method::cvode_bdf;
    mem_.reset(check_created(CVodeCreate(bdf ? CV_BDF : CV_ADAMS, ctx), "CVodeCreate"));
    void* m = mem_.get();
    check(CVodeSetErrHandlerFn(m, record_sundials_error, static_cast<Stepper*>(this)),
          "CVodeSetErrHandlerFn");
    check(CVodeInit(m, tree_rhs, t0, y0), "CVodeInit");
    check(CVodeSStolerances(m, s.relative_tolerance, s.absolute_tolerance), "CVodeSStolerances");
    check(CVodeSetUserData(m, &ode_), "CVodeSetUserData");
    check(CVodeSetMaxNumSteps(m, s.max_steps), "CVodeSetMaxNumSteps");
    if (s.max_step > 0.0) check(CVodeSetMaxStep(m, s.max_step), "CVodeSetMaxStep");
    if (s.initial_step > 0.0) check(CVodeSetInitStep(m, s.initial_step), "CVodeSetInitStep");
    if (bdf) {
      const auto n = N_VGetLength(y0);
      matrix_.reset(check_created(SUNDenseMatrix(n, n, ctx), "SUNDenseMatrix"));
      linear_.reset(check_created(SUNLinSol_Dense(y0, matrix_.get(), ctx), "SUNLinSol_Dense"));
      check(CVodeSetLinearSolver(m, linear_.get(), matrix_.get()), "CVodeSetLinearSolver");
    } else {
      nonlinear_.reset(
          check_created(SUNNonlinSol_FixedPoint(y0, 0, ctx), "SUNNonlinSol_FixedPoint"));
      check(CVodeSetNonlinearSolver(m, nonlinear_.get()), "CVodeSetNonlinearSolver");
    }
  }

  AdvanceResult step(double tout, N_Vector y, double& t) override {
    const int flag = CVode(mem_.get(), tout, y, &t, CV_ONE_STEP);
    if (flag >= 0) return AdvanceResult::stepped;
    failure_ = classify(flag);
    return AdvanceResult::failed;
  }

  void interpolate(double t, N_Vector y) override { check(CVodeGetDky(mem_.get(), t, 0, y), "CVodeGetDky"); }

  void restart(double t, N_Vector y) override { check(CVodeReInit(mem_.get(), t, y), "CVodeReInit"); }

  IntegratorStats counters() override {
    IntegratorStats s;
    void* m = mem_.get();
    long nni_fails = 0;
    CVodeGetNumSteps(m, &s.steps);
    CVodeGetNumRhsEvals(m, &s.rhs_evaluations);
    CVodeGetNumErrTestFails(m, &s.error_test_failures);
    CVodeGetNumNonlinSolvConvFails(m, &nni_fails);
    s.nonlinear_convergence_failures = nni_fails;
    if (linear_) {  // difference-quotient Jacobian columns cost RHS evaluations too
      long jac_rhs = 0;
      CVodeGetNumLinRhsEvals(m, &jac_rhs);
      s.rhs_evaluations += jac_rhs;
    }
    return s;
  }

  double current_time() override {
    double t = 0.0;
    CVodeGetCurrentTime(mem_.get(), &t);
    return t;
  }

 private:
  TreeOde& ode_;
  sundials::Matrix matrix_;
  sundials::LinearSolver linear_;
  sundials::NonlinearSolver nonlinear_;
  sundials::CvodeMemory mem_;  // last: freed first, before the solvers it uses
};

}  // namespace

std::unique_ptr<Stepper> make_cvode_stepper(TreeOde& ode, const IntegratorSettings& s, double t0,
                                            N_Vector y0, SUNContext ctx) {
  return std::make_unique<CvodeStepper>(ode, s, t0, y0, ctx);
}

}  // namespace treedyn
