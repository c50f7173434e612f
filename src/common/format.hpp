// Numbers as text for people and for job files.
#pragma once

#include <string>

namespace treedyn {

// The shortest form that reads back to the same double (e.g. 1e-07, -2.5).
std::string format_number(double v);
// `v` to `digits` significant digits (%g): a derived value for people.
std::string format_digits(double v, int digits);

}  // namespace treedyn
