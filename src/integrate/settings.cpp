#include "integrate/settings.hpp"

namespace treedyn {

std::string_view name(Method m) {
  switch (m) {
    case Method::cvode_adams:
      return "cvode_adams";
    case Method::cvode_bdf:
      return "cvode_bdf";
    case Method::erk_dormand_prince:
      return "erk_dormand_prince";
    case Method::erk_verner:
      return "erk_verner";
  }
  return "?";
}

bool parse_method(std::string_view text, Method& out) {
  for (Method m : {Method::cvode_adams, Method::cvode_bdf, Method::erk_dormand_prince,
                   Method::erk_verner}) {
    if (text == name(m)) {
      out = m;
      return true;
    }
  }
  return false;
}

std::string_view name(FailureKind f) {
  switch (f) {
    case FailureKind::none:
      return "none";
    case FailureKind::too_much_work:
      return "too_much_work";
    case FailureKind::too_much_accuracy:
      return "too_much_accuracy";
    case FailureKind::error_test_failures:
      return "error_test_failures";
    case FailureKind::convergence_failures:
      return "convergence_failures";
    case FailureKind::nonfinite_state:
      return "nonfinite_state";
    case FailureKind::setup:
      return "setup";
    case FailureKind::other:
      return "other";
  }
  return "?";
}

}  // namespace treedyn
