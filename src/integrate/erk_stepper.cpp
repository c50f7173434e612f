// ARKODE ERKStep with an embedded explicit Runge-Kutta pair.
#include <arkode/arkode_erkstep.h>

#include <memory>
#include <type_traits>
#include <vector>

#include "integrate/stepper.hpp"

namespace treedyn {
namespace {

using sundials::check;
using sundials::check_created;

FailureKind classify(int flag) {
  switch (flag) {
    case ARK_TOO_MUCH_WORK:
      return FailureKind::too_much_work;
    case ARK_TOO_MUCH_ACC:
      return FailureKind::too_much_accuracy;
    case ARK_ERR_FAILURE:
      return FailureKind::error_test_failures;
    case ARK_RHSFUNC_FAIL:
    case ARK_REPTD_RHSFUNC_ERR:
    case ARK_UNREC_RHSFUNC_ERR:
    case ARK_FIRST_RHSFUNC_ERR:
      return FailureKind::nonfinite_state;
    default:
      return FailureKind::other;
  }
}

struct TableDeleter {
  void operator()(ARKodeButcherTable t) const { ARKodeButcherTable_Free(t); }
};
using Table = std::unique_ptr<std::remove_pointer_t<ARKodeButcherTable>, TableDeleter>;

// Verner's 6(5) pair with one stage appended so that it is truly "first same
// as last": stage 9 = f(t + h, y_{n+1}) (c = 1, A row = b, weights 0).
// SUNDIALS 6.4 treats every table whose last c is 1 as FSAL (llnl/sundials
// issue #311); ARKODE_VERNER_8_5_6 is not, and used as shipped it reuses a
// wrong stage and drops to third order. With the appended stage the reuse is
// right and a step still costs 8 new right-hand sides.
Table fsal_verner_table() {
  Table verner(check_created(ARKodeButcherTable_LoadERK(ARKODE_VERNER_8_5_6),
                             "ARKodeButcherTable_LoadERK"));
  const int s = verner->stages;  // 8
  const int t = s + 1;
  std::vector<double> c(t, 0.0), A(static_cast<std::size_t>(t * t), 0.0), b(t, 0.0), d(t, 0.0);
  for (int i = 0; i < s; ++i) {
    c[i] = verner->c[i];
    b[i] = verner->b[i];
    d[i] = verner->d[i];
    for (int j = 0; j < s; ++j) A[static_cast<std::size_t>(i * t + j)] = verner->A[i][j];
    A[static_cast<std::size_t>(s * t + i)] = verner->b[i];
  }
  c[s] = 1.0;
  return Table(check_created(ARKodeButcherTable_Create(t, verner->q, verner->p, c.data(), A.data(),
                                                        b.data(), d.data()),
                             "ARKodeButcherTable_Create"));
}

class ErkStepper final : public Stepper {
 public:
  ErkStepper(TreeOde& ode, const IntegratorSettings& s, double t0, N_Vector y0, SUNContext ctx)
      : ode_(ode) {
    mem_.reset(check_created(ERKStepCreate(tree_rhs, t0, y0, ctx), "ERKStepCreate"));
    void* m = mem_.get();
    check(ERKStepSetErrHandlerFn(m, record_sundials_error, static_cast<Stepper*>(this)),
          "ERKStepSetErrHandlerFn");
    check(ERKStepSStolerances(m, s.relative_tolerance, s.absolute_tolerance),
          "ERKStepSStolerances");
    check(ERKStepSetUserData(m, &ode_), "ERKStepSetUserData");
    if (s.method == Method::erk_verner)
      check(ERKStepSetTable(m, fsal_verner_table().get()), "ERKStepSetTable");  // copies it
    else
      check(ERKStepSetTableNum(m, ARKODE_DORMAND_PRINCE_7_4_5), "ERKStepSetTableNum");
    check(ERKStepSetMaxNumSteps(m, s.max_steps), "ERKStepSetMaxNumSteps");
    if (s.max_step > 0.0) check(ERKStepSetMaxStep(m, s.max_step), "ERKStepSetMaxStep");
    if (s.initial_step > 0.0) check(ERKStepSetInitStep(m, s.initial_step), "ERKStepSetInitStep");
  }

  AdvanceResult step(double tout, N_Vector y, double& t) override {
    const int flag = ERKStepEvolve(mem_.get(), tout, y, &t, ARK_ONE_STEP);
    if (flag >= 0) return AdvanceResult::stepped;
    failure_ = classify(flag);
    return AdvanceResult::failed;
  }

  void interpolate(double t, N_Vector y) override { check(ERKStepGetDky(mem_.get(), t, 0, y), "ERKStepGetDky"); }

  void restart(double t, N_Vector y) override {
    check(ERKStepReInit(mem_.get(), tree_rhs, t, y), "ERKStepReInit");
  }

  IntegratorStats counters() override {
    IntegratorStats s;
    void* m = mem_.get();
    ERKStepGetNumSteps(m, &s.steps);
    ERKStepGetNumRhsEvals(m, &s.rhs_evaluations);
    ERKStepGetNumErrTestFails(m, &s.error_test_failures);
    return s;
  }

  double current_time() override {
    double t = 0.0;
    ERKStepGetCurrentTime(mem_.get(), &t);
    return t;
  }

 private:
  TreeOde& ode_;
  sundials::ErkMemory mem_;
};

}  // namespace

std::unique_ptr<Stepper> make_erk_stepper(TreeOde& ode, const IntegratorSettings& s, double t0,
                                          N_Vector y0, SUNContext ctx) {
  return std::make_unique<ErkStepper>(ode, s, t0, y0, ctx);
}

}  // namespace treedyn
