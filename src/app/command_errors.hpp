// The errors every command reports the same way: a refused job (JobError)
// exits 2, an output that cannot be written (h5::IoError) 4, anything else
// is a bug, 1. Each prints one line on stderr.
#pragma once

#include <functional>

namespace treedyn {

int exit_code_of(const std::function<int()>& command);

}  // namespace treedyn
