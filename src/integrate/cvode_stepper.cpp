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

constexpr std::pair<int, FailureKind> kFailures[] = {
    {CV_TOO_MUCH_WORK, FailureKind::too_much_work},       {CV_TOO_MUCH_ACC, FailureKind::too_much_accuracy},
    {CV_ERR_FAILURE, FailureKind::error_test_failures},   {CV_CONV_FAILURE, FailureKind::convergence_failures},
    {CV_LSETUP_FAIL, FailureKind::convergence_failures},  {CV_LSOLVE_FAIL, FailureKind::convergence_failures},
    {CV_NLS_FAIL, FailureKind::convergence_failures},     {CV_RHSFUNC_FAIL, FailureKind::nonfinite_state},
    {CV_REPTD_RHSFUNC_ERR, FailureKind::nonfinite_state}, {CV_UNREC_RHSFUNC_ERR, FailureKind::nonfinite_state},
    {CV_FIRST_RHSFUNC_ERR, FailureKind::nonfinite_state}};

const PackageCalls kCvode{CVodeSStolerances,   CVodeSetUserData, CVodeSetMaxNumSteps,
                          CVodeSetMaxStep,     CVodeSetInitStep, CVodeGetDky,
                          CVodeGetCurrentTime, kFailures,        "CVODE"};

class CvodeStepper final : public Stepper {
 public:
  CvodeStepper(TreeOde& ode, const IntegratorSettings& s, double t0, N_Vector y0, SUNContext ctx) : ode_(ode) {
    const bool bdf = s.method == Method::cvode_bdf;
    mem_.reset(check_created(CVodeCreate(bdf ? CV_BDF : CV_ADAMS, ctx), "CVodeCreate"));
    void* m = mem_.get();
#if SUNDIALS_VERSION_MAJOR >= 7
    capture_errors(ctx, m, nullptr, "");
#else
    capture_errors(ctx, m, CVodeSetErrHandlerFn, "CVodeSetErrHandlerFn");
#endif
    check(CVodeInit(m, tree_rhs, t0, y0), "CVodeInit");
    apply_settings(kCvode, m, ode_, s);
    if (bdf) {
      const auto n = N_VGetLength(y0);
      matrix_.reset(check_created(SUNDenseMatrix(n, n, ctx), "SUNDenseMatrix"));
      linear_.reset(check_created(SUNLinSol_Dense(y0, matrix_.get(), ctx), "SUNLinSol_Dense"));
      check(CVodeSetLinearSolver(m, linear_.get(), matrix_.get()), "CVodeSetLinearSolver");
    } else {
      nonlinear_.reset(check_created(SUNNonlinSol_FixedPoint(y0, 0, ctx), "SUNNonlinSol_FixedPoint"));
      check(CVodeSetNonlinearSolver(m, nonlinear_.get()), "CVodeSetNonlinearSolver");
    }
  }

  AdvanceResult step(double tout, N_Vector y, double& t) override {
    const int flag = CVode(mem_.get(), tout, y, &t, CV_ONE_STEP);
    if (flag >= 0) return AdvanceResult::stepped;
    failure_ = classify(kCvode, flag);
    return AdvanceResult::failed;
  }

  void interpolate(double t, N_Vector y) override { interpolate_with(kCvode, mem_.get(), t, y); }

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

  double current_time() override { return current_time_of(kCvode, mem_.get()); }

 private:
  TreeOde& ode_;
  sundials::Matrix matrix_;
  sundials::LinearSolver linear_;
  sundials::NonlinearSolver nonlinear_;
  sundials::CvodeMemory mem_;  // last: freed first, before the solvers it uses
};

}  // namespace

std::unique_ptr<Stepper> make_cvode_stepper(TreeOde& ode, const IntegratorSettings& s, double t0, N_Vector y0,
                                            SUNContext ctx) {
  return std::make_unique<CvodeStepper>(ode, s, t0, y0, ctx);
}

}  // namespace treedyn
