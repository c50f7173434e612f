// One sample of an ensemble on its own: integrated into a trajectory file
// (`treedyn-ensemble JOB --sample K -o FILE.h5`) or written as a standalone
// job (`--write-job K -o FILE.toml`). Serial: no MPI.
#pragma once

#include <cstdint>
#include <string>

#include "hdf5/provenance.hpp"

namespace treedyn {

// Both return the exit code and report errors on stderr.
int rerun_sample(const std::string& job_path, std::uint64_t k, const std::string& output_path,
                 bool quiet, const RunProvenance& run);
int write_sample_job(const std::string& job_path, std::uint64_t k, const std::string& output_path);

}  // namespace treedyn
