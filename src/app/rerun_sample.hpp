// One sample of an ensemble on its own: integrated into a trajectory file
// (`treedyn-ensemble JOB --sample K -o FILE.h5`) or written as a standalone
// job (`--write-job K -o FILE.toml`). Serial: no MPI.
#pragma once

#include <cstdint>
#include <string>

#include "hdf5/provenance.hpp"

namespace treedyn {

// Both return the exit code and report errors on stderr.
// `from`: the job's ensemble file, needed for a run of a subset
// simulation's level after 0 (its records replay the levels to its inputs).
int rerun_sample(const std::string& job_path, std::uint64_t k, const std::string& output_path, bool quiet,
                 const h5::RunProvenance& run, const std::string& from = "");
int write_sample_job(const std::string& job_path, std::uint64_t k, const std::string& output_path,
                     const std::string& from = "");

}  // namespace treedyn
