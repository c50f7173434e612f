// The ensemble run: every rank, rank 0 included, integrates samples; rank 0
// also writes the file.
//
//   1. rank 0 reads the job file and broadcasts its text; every rank parses
//      the same text, so a bad job fails identically everywhere before any
//      work (rank 0 prints the message);
//   2. rank 0 integrates the nominal run (the centre of the statistics) and
//      broadcasts it;
//   3. the pilot samples 0..K-1, round-robin over the ranks, fix each entry's
//      fixed-point scale and histogram range (an all-reduce of their min and
//      max deviations, so every rank gets the same calibration);
//   4. the other samples come from a shared work queue in blocks; records go
//      to rank 0 in bounded batches and are written by sample index;
//   5. the statistics are summed onto rank 0 exactly (integers, min, max).
#pragma once

#include <mpi.h>

#include <cstdint>
#include <string>

#include "hdf5/provenance.hpp"

namespace treedyn::parallel {

struct EnsembleOptions {
  RunProvenance provenance;  // command line, start time (ranks and hosts: filled by the driver)
  std::string job_path;
  std::string output_path;
  bool quiet = false;
  double progress_interval = 10.0;  // s between log lines when not on a terminal
  double checkpoint_every = 300.0;  // s between a rank's checkpoints; 0: none
  bool resume = false;              // continue from OUTPUT.checkpoint
  // --samples FIRST:END: only these sample indices, into a part file (the
  // merge command joins parts); end 0: the whole ensemble into HDF5.
  std::uint64_t first_sample = 0, end_sample = 0;
  bool part() const { return end_sample > 0; }
};

// Returns the process exit code (app/exit_codes.hpp), the same on all ranks.
int run_ensemble(MPI_Comm comm, const EnsembleOptions& options);

}  // namespace treedyn::parallel
