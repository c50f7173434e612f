// What an integration cost. One table lists the counters; summing, the
// record codec and both HDF5 writers read it, so they cannot drift apart.
#pragma once

#include <array>
#include <string_view>

namespace treedyn {

struct IntegratorStats {
  long steps = 0;
  long rhs_evaluations = 0;
  long error_test_failures = 0;
  long nonlinear_convergence_failures = 0;  // CVODE only
  long chart_changes = 0;                   // body orientations re-expressed in a fresh chart
  long restarts = 0;                        // integrator re-initialisations for them
  long chart_checks = 0;                    // chart-margin evaluations (one per step)
};

struct IntegratorStatField {
  std::string_view name;
  long IntegratorStats::*member;
  std::string_view description;
};

// In the order of the columns of /samples/integrator_stats.
inline constexpr std::array<IntegratorStatField, 7> kIntegratorStatFields{{
    {"steps", &IntegratorStats::steps, "integration steps taken"},
    {"rhs_evaluations", &IntegratorStats::rhs_evaluations,
     "right-hand-side evaluations (with the Jacobian's difference quotients)"},
    {"error_test_failures", &IntegratorStats::error_test_failures, "steps rejected by the error test"},
    {"nonlinear_convergence_failures", &IntegratorStats::nonlinear_convergence_failures,
     "nonlinear-solver convergence failures (CVODE)"},
    {"chart_changes", &IntegratorStats::chart_changes, "body orientations re-expressed in a fresh chart"},
    {"restarts", &IntegratorStats::restarts, "integrator restarts after chart changes"},
    {"chart_checks", &IntegratorStats::chart_checks, "chart-margin evaluations (one per step)"},
}};

inline void add(IntegratorStats& total, const IntegratorStats& part) {
  for (const IntegratorStatField& f : kIntegratorStatFields) total.*f.member += part.*f.member;
}

}  // namespace treedyn
