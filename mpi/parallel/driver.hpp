// The ensemble run. Every rank, rank 0 included, integrates samples; rank 0
// also writes the file. run_ensemble() is one pipeline of phases, below in
// the order they run; each returns an exit code (common/exit_codes.hpp) that is
// the same on every rank, kExitOk to go on:
//
//   read_job         rank 0 reads the job file once and sends its text; every
//                    rank parses the same text, so a bad job fails identically
//                    everywhere before any work (rank 0 prints the message)
//   check_range      --samples FIRST:END within the ensemble
//   check_memory     the statistics of every rank of a node fit its memory
//   open_output      rank 0: the output path (exit 4 before any work), stale
//                    temporaries of dead processes, the checkpoint: loaded
//                    with --resume, refused without it, else created
//   share_restored   a resumed run's calibration and finished samples
//   run_nominal      rank 0 integrates the nominal run (the statistics'
//                    centre) into the temporary output, and sends it
//   start_records    where records go (rank 0's writer, the others' senders),
//                    a resumed run's restored records, this rank's checkpoint
//   run_waves        the design's waves (ensemble/wave_plan.hpp), the pilot
//                    wave first: its deviations fix the calibration
//   stop_interrupted (a signal stopped the waves) checkpoints saved, the
//                    temporary output removed, the hint printed: exit 5
//   finish_run       statistics summed onto rank 0, the file (or part file)
//                    written and renamed, the checkpoint removed
//
// Signals (process/signals.hpp): the first SIGTERM, SIGINT, SIGHUP or
// SIGUSR1 saves this rank's checkpoint at once, on the signal thread; the
// main thread abandons the sample in flight at its next output time and
// stops; the other ranks see the work queue's flag and stop too.
#pragma once

#include <mpi.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "analysis/answers.hpp"
#include "analysis/wave_plans.hpp"
#include "ensemble/index_ranges.hpp"
#include "ensemble/progress.hpp"
#include "ensemble/rank_results.hpp"
#include "ensemble/sample_runner.hpp"
#include "hdf5/ensemble_file.hpp"
#include "hdf5/provenance.hpp"
#include "parallel/record_sink.hpp"
#include "parallel/test_hooks.hpp"
#include "process/output_lock.hpp"

namespace treedyn::parallel {

struct EnsembleOptions {
  h5::RunProvenance provenance;  // command line, start time (ranks and hosts: filled by the driver)
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
  TestHooks test;  // the tests' seam (hidden options); inert unless set
};

// Returns the process exit code, the same on all ranks.
int run_ensemble(MPI_Comm comm, const EnsembleOptions& options);

// What is configured once, the same on every rank for the whole run.
struct RunSetup {
  RunSetup(MPI_Comm comm, const EnsembleOptions& options, const Job& job, const EnsembleSpec& spec);

  MPI_Comm comm;
  int rank = 0, size = 1;
  const EnsembleOptions& options;
  const Job& job;
  const EnsembleSpec& spec;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  // The samples this run owns, [first, end): the whole ensemble unless a part.
  std::uint64_t first = 0, end = 0;
  bool owns(std::uint64_t k) const { return k >= first && k < end; }
  // Rows of a unit (ensemble/capacity.hpp: unit_rows), 0: none; never for a
  // part, whose records go into its part file. Set once the rows' layout
  // is known (EnsembleRun).
  std::size_t unit_rows = 0;
  // A part's checkpoint belongs to its range (id); the part file to the job (job_id).
  persistence::RunIdentity job_id, id;
  std::filesystem::path checkpoint_dir;
};

// What the design owns: its waves, and what decides the next one.
struct DesignState {
  explicit DesignState(const EnsembleSpec& spec) : plan(analysis::make_wave_plan(spec)) {}

  std::unique_ptr<ensemble::WavePlan> plan;
  std::uint64_t samples_used = 0;                // the end of the last wave run: [ensemble.stop] may end before `end`
  std::optional<ensemble::ResponseTable> table;  // rank 0, with responses: the answers and the plans' decisions
};

// What this rank owns: its runner, what it restored, its results and
// checkpoint, its records' way out, its output (rank 0) and its counters.
struct RankState {
  RankState(const Job& job, const EnsembleSpec& spec) : runner(job, spec) {}

  ensemble::SampleRunner runner;
  // Rank 0: the output's lock (process/output_lock.hpp), held from before
  // anything of the output is touched to the end; released last.
  std::optional<process::OutputLock> lock;

  std::optional<persistence::RestoredRun> restored;  // rank 0's, whole; the others': calibration only
  ensemble::IndexRanges finished;                    // samples a resumed run already has
  std::uint64_t restored_samples = 0, generation = 0;
  std::vector<double> nominal;
  statistics::ToleranceCheck tolerance;  // the pilot's (every rank), or restored (rank 0)

  std::unique_ptr<h5::EnsembleWriter> writer;  // rank 0, whole ensembles
  std::unique_ptr<ensemble::Progress> progress;
  std::vector<SampleRecord> part_records;  // rank 0, parts
  std::unique_ptr<RecordSink> sink;
  RecordWriter* records = nullptr;  // rank 0's view of the sink
  ensemble::RankResults results;
  bool checkpoints = false;                                           // on, and common.state written (or restored)
  std::optional<statistics::EnsembleStatistics> restored_statistics;  // rank 0

  double busy_seconds = 0.0, busy_cpu_seconds = 0.0;
  std::uint64_t samples_run = 0;

  std::uint64_t kept_after_pilot = 0, kept = 0;  // for options.test.hold_after
};

// Everything one rank knows of the run (the phases' shared data), by trade.
struct EnsembleRun : RunSetup, DesignState, RankState {
  EnsembleRun(MPI_Comm c, const EnsembleOptions& o, const Job& j, const EnsembleSpec& s);
};

// Runs `work` on rank 0 alone and gives every rank its exit code. A file
// error becomes exit 4, an unusable checkpoint exit 2, each with its message.
int on_rank_zero(EnsembleRun& run, const std::function<int()>& work);

// A phase's code for "the output is this job's, complete, and nothing is
// left to resume": every rank ends at once with exit 0.
inline constexpr int kAlreadyDone = -1;

// Every rank failed to allocate alike (the statistics): all exit 6.
struct OutOfMemoryEverywhere {};

int check_range(EnsembleRun& run);
int check_memory(EnsembleRun& run);
int open_output(EnsembleRun& run);
int share_restored(EnsembleRun& run);
int run_nominal(EnsembleRun& run);
int start_records(EnsembleRun& run);
int run_waves(EnsembleRun& run);
int stop_interrupted(EnsembleRun& run, bool resumable);
int finish_run(EnsembleRun& run);

}  // namespace treedyn::parallel
