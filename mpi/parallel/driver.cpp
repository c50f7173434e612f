#include "parallel/driver.hpp"

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <new>
#include <sstream>

#include "common/exit_codes.hpp"
#include "designs/design_rules.hpp"
#include "ensemble/capacity.hpp"
#include "job/job_error.hpp"
#include "job/sample_job.hpp"
#include "parallel/collectives.hpp"
#include "parallel/memory_check.hpp"
#include "process/atomic_file.hpp"
#include "process/signals.hpp"

namespace treedyn::parallel {
namespace fs = std::filesystem;

RunSetup::RunSetup(MPI_Comm c, const EnsembleOptions& o, const Job& j, const EnsembleSpec& s)
    : comm(c), options(o), job(j), spec(s) {
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  first = options.part() ? options.first_sample : 0;
  end = options.part() ? options.end_sample : spec.runs;
  job_id = persistence::run_identity(job.text, h5::build_identity());
  id = options.part()
           ? persistence::run_identity(job.text + "\n# --samples " + std::to_string(first) + ":" + std::to_string(end),
                                       h5::build_identity())
           : job_id;
  checkpoint_dir = persistence::checkpoint_directory(options.output_path);
}

EnsembleRun::EnsembleRun(MPI_Comm c, const EnsembleOptions& o, const Job& j, const EnsembleSpec& s)
    : RunSetup(c, o, j, s), DesignState(s), RankState(j, s) {
  // A part's records go into its part file; an adaptive design's arrive as
  // its waves make them (chain by chain), not in units.
  if (options.part() || designs::rules_of(spec.design).adaptive(spec)) return;
  const ensemble::SampleRows rows(spec, runner.layout(), runner.final_state_size());
  unit_rows = options.test.unit_rows.value_or(ensemble::unit_rows(spec, size, ensemble::most_unit_rows(rows)));
}

namespace {

// Rank 0 reads the job file once and sends its text; every rank parses the
// same text, so all refuse a bad job alike and no collective is left waiting.
int read_job(MPI_Comm comm, int rank, const std::string& path, Job& job, EnsembleSpec& spec) {
  std::string text;
  int ok = 1;
  if (rank == 0) {
    try {
      const std::vector<char> bytes = process::read_file(path);
      text.assign(bytes.begin(), bytes.end());
    } catch (const process::FileError&) {
      ok = 0;
      std::cerr << "error: " << path << ": cannot open the job file for reading\n";
    }
  }
  if (broadcast(comm, ok) == 0) return kExitBadInput;
  std::vector<char> bytes(text.begin(), text.end());
  broadcast(comm, bytes);
  try {
    EnsembleJob read = read_ensemble_job(JobDocument::parse(std::string(bytes.begin(), bytes.end()), path));
    job = std::move(read.job);
    spec = std::move(read.spec);
  } catch (const JobError& e) {
    if (rank == 0) std::cerr << "error: " << e.what() << "\n";
    return kExitBadInput;
  }
  return kExitOk;
}

constexpr const char* memory_advice =
    "the job asks for more than this node (or its memory limit) gives; use fewer ranks per node, fewer "
    "histogram_bins, output times or quantities";

// A failed run leaves nothing half-written: the temporary output goes with
// the writer, and a checkpoint directory that no resume could restore a
// sample from goes too.
int abandon(EnsembleRun& run, int code) {
  run.results.await_final_save();  // a failure after the last wave: its save first
  if (run.rank == 0) {
    run.writer.reset();
    try {
      if (!persistence::checkpoint_holds_samples(run.checkpoint_dir))
        persistence::remove_checkpoint(run.checkpoint_dir);
    } catch (const process::FileError&) {
    }
  }
  return code;
}

int run_phases(EnsembleRun& run) {
  for (auto* phase : {check_range, check_memory, open_output, share_restored, run_nominal, start_records}) {
    const int code = phase(run);
    if (code == kAlreadyDone) return kExitOk;
    if (code != kExitOk) return abandon(run, code);
  }
  const int waves = run_waves(run);
  if (waves != kExitOk) return waves == kExitInterrupted ? waves : abandon(run, waves);
  const int code = finish_run(run);
  return code == kExitOk ? code : abandon(run, code);
}

}  // namespace

int on_rank_zero(EnsembleRun& run, const std::function<int()>& work) {
  int code = kExitOk;
  if (run.rank == 0) {
    try {
      code = work();
    } catch (const process::FileError& e) {
      std::cerr << "error: " << e.what() << "\n";
      code = kExitIo;
    } catch (const persistence::CheckpointError& e) {
      std::cerr << "error: " << e.what() << "\n";
      code = kExitBadInput;
    }
  }
  return broadcast(run.comm, code);
}

int check_range(EnsembleRun& run) {
  const bool adaptive = designs::rules_of(run.spec.design).adaptive(run.spec);
  if (run.options.part() && (run.spec.stop || adaptive)) {
    if (run.rank == 0)
      std::cerr << "error: --samples: " << (run.spec.stop ? "[ensemble.stop]" : name(run.spec.design))
                << " decides from every sample before each check point, so its ensemble runs as one job (any "
                   "number of ranks), not in parts\n";
    return kExitBadInput;
  }
  if (run.first < run.end && run.end <= run.spec.runs) return kExitOk;
  if (run.rank == 0)
    std::cerr << "error: --samples " << run.options.first_sample << ":" << run.options.end_sample
              << " is not a range of this ensemble's sample indices: FIRST < END <= " << run.spec.runs << "\n";
  return kExitBadInput;
}

int check_memory(EnsembleRun& run) {
  return memory_fits(run.comm, statistics_bytes(run.job, run.spec)) ? kExitOk : kExitMemory;
}

int run_ensemble(MPI_Comm comm, const EnsembleOptions& options) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  Job job;
  EnsembleSpec spec;
  if (const int code = read_job(comm, rank, options.job_path, job, spec); code != kExitOk) return code;
  EnsembleRun run(comm, options, job, spec);
  // The first signal saves this rank's checkpoint at once (on the signal
  // thread); the main thread stops at its next output time.
  const process::StopOnSignals stop([&run](int) { run.results.stop(); });
  try {
    return run_phases(run);
  } catch (const OutOfMemoryEverywhere&) {
    if (run.rank == 0) std::cerr << "error: out of memory for the statistics: " << memory_advice << "\n";
    return abandon(run, kExitMemory);
  } catch (const std::bad_alloc&) {
    // Where every rank allocates alike (the statistics) the ranks agree and
    // all exit 6; this is an allocation on one rank alone. Alone, exit 6;
    // with others possibly waiting in a collective, MPI_Abort ends them all.
    std::cerr << "error: out of memory on rank " << run.rank << ": " << memory_advice << "\n";
    abandon(run, kExitMemory);
    if (run.size > 1) MPI_Abort(run.comm, kExitMemory);
    return kExitMemory;
  }
}

}  // namespace treedyn::parallel
