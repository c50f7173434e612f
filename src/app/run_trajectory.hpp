// One trajectory from a model and an initial state into an HDF5 file, with
// the run's summary: `treedyn run` and `treedyn-ensemble --sample`.
#pragma once

#include <string>

#include "hdf5/trajectory_file.hpp"
#include "job/job.hpp"

namespace treedyn {

// Returns the exit code (common/exit_codes.hpp). Throws h5::IoError.
int run_trajectory(const Job& job, const Model& model, const InitialState& initial, const std::string& output_path,
                   bool quiet, const h5::RunProvenance& run, const h5::SampleOrigin* sample = nullptr);

}  // namespace treedyn
