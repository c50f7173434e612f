// The HDF5 file of one trajectory (`treedyn run`).
#pragma once

#include <filesystem>

#include "integrate/settings.hpp"
#include "job/job.hpp"
#include "output/recorder.hpp"

namespace treedyn {

// Writes /time, one dataset per quantity, and the run's attributes, under a
// temporary name renamed into place when complete. Throws h5::IoError.
void write_trajectory(const std::filesystem::path& path, const Job& job,
                      const TrajectoryRecorder& recorder, const IntegrationOutcome& outcome);

}  // namespace treedyn
