// Errors raised while reading or validating a user's description.
#pragma once

#include <stdexcept>
#include <string>

namespace treedyn {

// A description the solver refuses; the message names the offending body or
// joint and says what is allowed.
class ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace treedyn
