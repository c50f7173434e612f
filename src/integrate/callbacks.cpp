// The C entry points SUNDIALS calls. Return codes follow SUNDIALS: 0 ok,
// > 0 recoverable (the step is retried smaller), < 0 unrecoverable.
#include <exception>
#include <span>

#include "integrate/stepper.hpp"

namespace treedyn {
namespace {

std::span<double> view(N_Vector v) {
  return {N_VGetArrayPointer(v), static_cast<std::size_t>(N_VGetLength(v))};
}

}  // namespace

int tree_rhs(double t, N_Vector y, N_Vector y_dot, void* ode) {
  try {
    // A non-finite result is recoverable: a smaller step may stay finite.
    return static_cast<TreeOde*>(ode)->rhs(t, view(y), view(y_dot)) ? 0 : 1;
  } catch (...) {
    return -1;
  }
}

void record_sundials_error(int, const char* module, const char* function, char* msg,
                           void* stepper) {
  try {
    auto* s = static_cast<Stepper*>(stepper);
    s->message_ = std::string(module) + "/" + function + ": " + msg;
  } catch (...) {
    // Losing the text is better than letting an exception into C.
  }
}

}  // namespace treedyn
