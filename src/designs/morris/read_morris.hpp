// The job reader's part of design = "morris".
#pragma once

#include <cstdint>

#include "job/ensemble_spec.hpp"
#include "job/toml_view.hpp"

namespace treedyn::designs {

// Reads [ensemble.morris] into s.morris and sets s.samples (trajectories)
// and s.runs. Needs the units (read_groups) first. Throws JobError.
void read_morris(const TomlView& ensemble, EnsembleSpec& s, std::uint64_t max_runs);

}  // namespace treedyn::designs
