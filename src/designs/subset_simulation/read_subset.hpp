// The job reader's part of design = "subset_simulation".
#pragma once

#include <cstdint>

#include "job/ensemble_spec.hpp"
#include "job/toml_view.hpp"

namespace treedyn::designs {

// Reads [ensemble.subset] into s.subset and sets s.runs, the most its
// levels can make (at most `max_runs`). Needs the responses first. Throws
// JobError.
void read_subset(const TomlView& ensemble, EnsembleSpec& s, std::uint64_t max_runs);

}  // namespace treedyn::designs
