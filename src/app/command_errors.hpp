// The errors every command reports the same way: a refused job (JobError)
// or command line (CommandRefused) exits 2, an output that cannot be written (h5::IoError) 4, anything else
// is a bug, 1. Each prints one line on stderr.
#pragma once

#include <functional>
#include <stdexcept>

namespace treedyn {

// A command line that cannot be served as given (exit 2): the message says
// what was wrong and what to do instead.
class CommandRefused : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

int exit_code_of(const std::function<int()>& command);

}  // namespace treedyn
