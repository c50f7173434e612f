// Errors raised while reading or validating a user's description.
#pragma once

#include <stdexcept>
#include <string>

namespace treedyn {

// A description the solver refuses; the message names the offending body or
// joint and says what is allowed. `subject` is that body's name when the
// error concerns one body (readers use it to point at the body's definition).
class ModelError : public std::runtime_error {
 public:
  explicit ModelError(const std::string& message, std::string subject = {})
      : std::runtime_error(message), subject_(std::move(subject)) {}
  const std::string& subject() const { return subject_; }

 private:
  std::string subject_;
};

}  // namespace treedyn
