// What the caller chooses about integration and what comes back.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "common/enum_names.hpp"
#include "integrate/integrator_stats.hpp"

namespace treedyn {

enum class Method {
  cvode_adams,         // CVODE, variable-order Adams-Moulton (orders 1-12), fixed-point iteration
  cvode_bdf,           // CVODE, BDF (orders 1-5), Newton with a dense difference-quotient Jacobian
  erk_dormand_prince,  // ARKODE ERKStep, Dormand-Prince 5(4) embedded pair
  erk_verner,          // ARKODE ERKStep, Verner 6(5) embedded pair
};

inline constexpr NameTable<Method, 4> kMethodNames{{{Method::cvode_adams, "cvode_adams"},
                                                    {Method::cvode_bdf, "cvode_bdf"},
                                                    {Method::erk_dormand_prince, "erk_dormand_prince"},
                                                    {Method::erk_verner, "erk_verner"}}};
inline std::string_view name(Method m) { return name_in(kMethodNames, m); }
inline bool parse_method(std::string_view text, Method& out) { return parse_in(kMethodNames, text, out); }

struct IntegratorSettings {
  Method method = Method::cvode_adams;
  double relative_tolerance = 1e-8;
  double absolute_tolerance = 1e-10;
  long max_steps = 100000;    // per output interval (SUNDIALS' mxstep)
  double max_step = 0.0;      // 0: no limit
  double initial_step = 0.0;  // 0: the integrator's estimate
};

enum class FailureKind {
  none,
  too_much_work,         // max_steps taken before the next output time
  too_much_accuracy,     // tolerances below what double precision can give
  error_test_failures,   // repeated error-test failures (step size underflow)
  convergence_failures,  // repeated nonlinear-solver failures (CVODE)
  nonfinite_state,       // NaN or infinity in the state or its derivative
  setup,                 // invalid settings or a SUNDIALS set-up failure
  other,
};

inline constexpr NameTable<FailureKind, 8> kFailureNames{{{FailureKind::none, "none"},
                                                          {FailureKind::too_much_work, "too_much_work"},
                                                          {FailureKind::too_much_accuracy, "too_much_accuracy"},
                                                          {FailureKind::error_test_failures, "error_test_failures"},
                                                          {FailureKind::convergence_failures, "convergence_failures"},
                                                          {FailureKind::nonfinite_state, "nonfinite_state"},
                                                          {FailureKind::setup, "setup"},
                                                          {FailureKind::other, "other"}}};
inline std::string_view name(FailureKind f) { return name_in(kFailureNames, f); }

// A body's orientation re-expressed in a fresh chart, at the end of a step.
struct ChartChange {
  double time = 0.0;
  int body = 0;  // user order
};

struct IntegrationOutcome {
  FailureKind failure = FailureKind::none;
  double time_reached = 0.0;
  std::string message;  // SUNDIALS' own words, when it gave any
  IntegratorStats stats;
  std::vector<ChartChange> chart_changes;  // in time order
  bool ok() const { return failure == FailureKind::none; }
};

}  // namespace treedyn
