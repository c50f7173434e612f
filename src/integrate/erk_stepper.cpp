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

constexpr std::pair<int, FailureKind> kFailures[] = {
    {ARK_TOO_MUCH_WORK, FailureKind::too_much_work},       {ARK_TOO_MUCH_ACC, FailureKind::too_much_accuracy},
    {ARK_ERR_FAILURE, FailureKind::error_test_failures},   {ARK_RHSFUNC_FAIL, FailureKind::nonfinite_state},
    {ARK_REPTD_RHSFUNC_ERR, FailureKind::nonfinite_state}, {ARK_UNREC_RHSFUNC_ERR, FailureKind::nonfinite_state},
    {ARK_FIRST_RHSFUNC_ERR, FailureKind::nonfinite_state}};

// SUNDIALS 7.1 calls these ARKODE's own, for every stepper; 6.4 names them
// per stepper.
#if SUNDIALS_VERSION_MAJOR >= 7
const PackageCalls kErkStep{ARKodeSStolerances,   ARKodeSetUserData, ARKodeSetMaxNumSteps,
                            ARKodeSetMaxStep,     ARKodeSetInitStep, ARKodeGetDky,
                            ARKodeGetCurrentTime, kFailures,         "ARKODE ERKStep"};
constexpr auto kEvolve = ARKodeEvolve;
constexpr auto kNumSteps = ARKodeGetNumSteps;
constexpr auto kNumErrTestFails = ARKodeGetNumErrTestFails;
#else
const PackageCalls kErkStep{ERKStepSStolerances,   ERKStepSetUserData, ERKStepSetMaxNumSteps,
                            ERKStepSetMaxStep,     ERKStepSetInitStep, ERKStepGetDky,
                            ERKStepGetCurrentTime, kFailures,          "ARKODE ERKStep"};
constexpr auto kEvolve = ERKStepEvolve;
constexpr auto kNumSteps = ERKStepGetNumSteps;
constexpr auto kNumErrTestFails = ERKStepGetNumErrTestFails;
#endif

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
  Table verner(check_created(ARKodeButcherTable_LoadERK(ARKODE_VERNER_8_5_6), "ARKodeButcherTable_LoadERK"));
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
  return Table(check_created(ARKodeButcherTable_Create(t, verner->q, verner->p, c.data(), A.data(), b.data(), d.data()),
                             "ARKodeButcherTable_Create"));
}

class ErkStepper final : public Stepper {
 public:
  ErkStepper(TreeOde& ode, const IntegratorSettings& s, double t0, N_Vector y0, SUNContext ctx) : ode_(ode) {
    mem_.reset(check_created(ERKStepCreate(tree_rhs, t0, y0, ctx), "ERKStepCreate"));
    void* m = mem_.get();
#if SUNDIALS_VERSION_MAJOR >= 7
    capture_errors(ctx, m, nullptr, "");
#else
    capture_errors(ctx, m, ERKStepSetErrHandlerFn, "ERKStepSetErrHandlerFn");
#endif
    apply_settings(kErkStep, m, ode_, s);
    if (s.method == Method::erk_verner)
      check(ERKStepSetTable(m, fsal_verner_table().get()), "ERKStepSetTable");  // copies it
    else
      check(ERKStepSetTableNum(m, ARKODE_DORMAND_PRINCE_7_4_5), "ERKStepSetTableNum");
  }

  AdvanceResult step(double tout, N_Vector y, double& t) override {
    const int flag = kEvolve(mem_.get(), tout, y, &t, ARK_ONE_STEP);
    if (flag >= 0) return AdvanceResult::stepped;
    failure_ = classify(kErkStep, flag);
    return AdvanceResult::failed;
  }

  void interpolate(double t, N_Vector y) override { interpolate_with(kErkStep, mem_.get(), t, y); }

  void restart(double t, N_Vector y) override { check(ERKStepReInit(mem_.get(), tree_rhs, t, y), "ERKStepReInit"); }

  IntegratorStats counters() override {
    IntegratorStats s;
    void* m = mem_.get();
    kNumSteps(m, &s.steps);
    ERKStepGetNumRhsEvals(m, &s.rhs_evaluations);
    kNumErrTestFails(m, &s.error_test_failures);
    return s;
  }

  double current_time() override { return current_time_of(kErkStep, mem_.get()); }

 private:
  TreeOde& ode_;
  sundials::ErkMemory mem_;
};

}  // namespace

std::unique_ptr<Stepper> make_erk_stepper(TreeOde& ode, const IntegratorSettings& s, double t0, N_Vector y0,
                                          SUNContext ctx) {
  return std::make_unique<ErkStepper>(ode, s, t0, y0, ctx);
}

}  // namespace treedyn
