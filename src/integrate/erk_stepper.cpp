// ARKODE ERKStep with an embedded explicit Runge-Kutta pair.
#include <arkode/arkode_erkstep.h>

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
    check(ERKStepSetTableNum(m, s.method == Method::erk_verner ? ARKODE_VERNER_8_5_6
                                                                : ARKODE_DORMAND_PRINCE_7_4_5),
          "ERKStepSetTableNum");
    check(ERKStepSetMaxNumSteps(m, s.max_steps), "ERKStepSetMaxNumSteps");
    if (s.max_step > 0.0) check(ERKStepSetMaxStep(m, s.max_step), "ERKStepSetMaxStep");
    if (s.initial_step > 0.0) check(ERKStepSetInitStep(m, s.initial_step), "ERKStepSetInitStep");
    check(ERKStepRootInit(m, ode_.root_count(), tree_roots), "ERKStepRootInit");
    std::vector<int> downwards(static_cast<std::size_t>(ode_.root_count()), -1);
    check(ERKStepSetRootDirection(m, downwards.data()), "ERKStepSetRootDirection");
    check(ERKStepSetNoInactiveRootWarn(m), "ERKStepSetNoInactiveRootWarn");
  }

  AdvanceResult advance(double tout, N_Vector y, double& t) override {
    const int flag = ERKStepEvolve(mem_.get(), tout, y, &t, ARK_NORMAL);
    if (flag == ARK_ROOT_RETURN) return AdvanceResult::root;
    if (flag >= 0) return AdvanceResult::reached;
    failure_ = classify(flag);
    return AdvanceResult::failed;
  }

  void restart(double t, N_Vector y) override {
    check(ERKStepReInit(mem_.get(), tree_rhs, t, y), "ERKStepReInit");
  }

  void root_flags(int* flags) override { check(ERKStepGetRootInfo(mem_.get(), flags), "ERKStepGetRootInfo"); }

  IntegratorStats counters() override {
    IntegratorStats s;
    void* m = mem_.get();
    ERKStepGetNumSteps(m, &s.steps);
    ERKStepGetNumRhsEvals(m, &s.rhs_evaluations);
    ERKStepGetNumErrTestFails(m, &s.error_test_failures);
    ERKStepGetNumGEvals(m, &s.root_evaluations);
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
