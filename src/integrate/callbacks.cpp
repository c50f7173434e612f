// The C entry points SUNDIALS calls. Return codes follow SUNDIALS: 0 ok,
// > 0 recoverable (the step is retried smaller), < 0 unrecoverable.
#include <exception>
#include <span>

#include "integrate/stepper.hpp"

namespace treedyn {
namespace {

std::span<double> view(N_Vector v) { return {N_VGetArrayPointer(v), static_cast<std::size_t>(N_VGetLength(v))}; }

}  // namespace

int tree_rhs(double t, N_Vector y, N_Vector y_dot, void* ode) {
  try {
    // A non-finite result is recoverable: a smaller step may stay finite.
    return static_cast<TreeOde*>(ode)->rhs(t, view(y), view(y_dot)) ? 0 : 1;
  } catch (...) {
    return -1;
  }
}

// Losing the text is better than letting an exception into C.
#if SUNDIALS_VERSION_MAJOR >= 7
void Stepper::record_error(int, const char* function, const char*, const char* message, SUNErrCode, void* stepper,
                           SUNContext) {
  try {
    static_cast<Stepper*>(stepper)->message_ = std::string(function) + ": " + message;
  } catch (...) {
  }
}
#else
void Stepper::record_error(int, const char* module, const char* function, char* message, void* stepper) {
  try {
    static_cast<Stepper*>(stepper)->message_ = std::string(module) + "/" + function + ": " + message;
  } catch (...) {
  }
}
#endif

void apply_settings(const PackageCalls& c, void* m, TreeOde& ode, const IntegratorSettings& s) {
  const std::string_view p = c.package;
  sundials::check(c.set_tolerances(m, s.relative_tolerance, s.absolute_tolerance), p, " tolerances");
  sundials::check(c.set_user_data(m, &ode), p, " user data");
  sundials::check(c.set_max_num_steps(m, s.max_steps), p, " max_steps");
  if (s.max_step > 0.0) sundials::check(c.set_max_step(m, s.max_step), p, " max_step");
  if (s.initial_step > 0.0) sundials::check(c.set_init_step(m, s.initial_step), p, " initial_step");
}

void interpolate_with(const PackageCalls& c, void* m, double t, N_Vector y) {
  sundials::check(c.get_dky(m, t, 0, y), c.package, " dense output");
}

double current_time_of(const PackageCalls& c, void* m) {
  sunrealtype t = 0.0;
  c.get_current_time(m, &t);
  return t;
}

FailureKind classify(const PackageCalls& c, int flag) {
  for (const auto& [code, kind] : c.failures)
    if (code == flag) return kind;
  return FailureKind::other;
}

}  // namespace treedyn
