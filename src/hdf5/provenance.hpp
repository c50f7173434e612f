// Where an output file came from: the run (UTC start and end, host, command
// line, job file), the build (version, git commit, build type, compiler) and
// the libraries, written as root attributes of every file treedyn writes.
#pragma once

#include <hdf5.h>

#include <string>
#include <vector>

namespace treedyn::h5 {

struct RunProvenance {
  std::string start_utc;  // ISO 8601, e.g. 2026-12-01T12:00:00Z
  std::string host;
  std::string command_line;  // argv joined by spaces, shell-quoted where needed
  std::string job_path;      // absolute
  int ranks = 1;
  std::vector<std::string> rank_hosts;  // per rank (MPI runs), else empty
  std::string mpi_library;              // MPI_Get_library_version; empty without MPI
};

// The run's start: now, this host, the command line.
RunProvenance start_provenance(int argc, const char* const* argv, const std::string& job_path);

// "treedyn VERSION, commit C, BUILD_TYPE, COMPILER": what a checkpoint must
// match to be resumed.
std::string build_identity();

// Root attributes: start_utc, end_utc (now), host, command_line, job_path,
// treedyn_version, git_commit, build_type, compiler, sundials_version,
// hdf5_version, eigen_version, tomlplusplus_version, mpi_library, ranks and
// rank_hosts. Throws IoError.
void write_provenance(hid_t root, const RunProvenance& run);

}  // namespace treedyn::h5
