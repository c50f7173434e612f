// `treedyn-ensemble JOB -o OUT.h5`: a Monte-Carlo ensemble of one job, run
// under mpirun (or alone as one rank).
#include <CLI/CLI.hpp>

#include <cstdlib>
#include <iostream>

#include "app/command_errors.hpp"
#include "app/merge_parts.hpp"
#include "app/model_summary.hpp"
#include "app/rerun_sample.hpp"
#include "common/exit_codes.hpp"
#include "ensemble/capacity.hpp"
#include "hdf5/hdf5.hpp"
#include "job/ensemble_spec.hpp"
#include "job/job_error.hpp"
#include "job/sample_job.hpp"
#include "parallel/driver.hpp"
#include "parallel/mpi_handles.hpp"
#include "process/atomic_file.hpp"
#include "process/signals.hpp"

namespace {

// --check: validate the job and its [ensemble], print what would run, run
// nothing. Rank 0's capacity counts what writing costs where the output
// would go (the output's directory, else the current one).
int check(const std::string& job_path, const std::string& output_path) {
  try {
    const auto [job, spec] = treedyn::read_ensemble_job(treedyn::JobDocument::read(job_path));
    treedyn::print_model_summary(std::cout, job);
    treedyn::print_ensemble_summary(std::cout, job, spec);
    treedyn::ensemble::Capacity capacity = treedyn::ensemble::measure_capacity(job, spec);
    treedyn::ensemble::measure_writing(capacity, treedyn::process::directory_of(output_path));
    treedyn::ensemble::print_capacity(std::cout, capacity, spec, "sample 0, timed now");
    std::cout << job_path << ": OK\n";
    return treedyn::kExitOk;
  } catch (const treedyn::JobError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return treedyn::kExitBadInput;
  }
}

// After an exception on one rank, the others may be waiting in a collective:
// MPI_Abort ends them all with this code. Alone, there is no one to wait.
int end_all(const treedyn::parallel::Session& session, int code) {
  if (session.size() > 1) MPI_Abort(MPI_COMM_WORLD, code);
  return code;
}

}  // namespace

// `merge -o OUT.h5 PART...`: serial, on rank 0.
int merge_command(int argc, char** argv, int rank) {
  using namespace treedyn;
  CLI::App app{
      "treedyn-ensemble merge: the part files of a split ensemble (--samples FIRST:END) into one "
      "ensemble file, bitwise identical in /stats and /samples to one run over the union"};
  std::vector<std::string> parts;
  std::string output;
  bool quiet = false;
  app.add_option("PART", parts, "part files written by treedyn-ensemble --samples")->required();
  app.add_option("-o,--output", output, "the merged ensemble file (HDF5), written atomically")->required();
  app.add_flag("-q,--quiet", quiet, "no summary");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = rank == 0 ? app.exit(e) : (e.get_exit_code() == 0 ? 0 : 1);
    return code == 0 ? kExitOk : kExitBadInput;
  }
  if (rank != 0) return kExitOk;
  return exit_code_of(
      [&] { return merge_parts(parts, output, quiet, h5::start_provenance(argc, argv, parts.front())); });
}

namespace {

// What the command line asks for.
struct CommandLine {
  treedyn::parallel::EnsembleOptions options;
  bool check_only = false;
  long long sample = 0, job_sample = 0;
  std::string sample_range, from;
  CLI::Option *sample_option = nullptr, *write_job_option = nullptr, *samples_option = nullptr;
};

void define_options(CLI::App& app, CommandLine& c) {
  app.set_version_flag("--version", std::string("treedyn-ensemble ") + TREEDYN_VERSION);
  app.footer(
      "Run under mpirun -np P (or alone for one rank). Exit codes: 0 ok, 1 internal error, "
      "2 bad input, 3 the nominal run failed, 4 output (I/O) failure, 5 interrupted by SIGTERM, "
      "SIGINT, SIGHUP or SIGUSR1 (resume with --resume), 6 not enough memory. Failed samples do not fail the job: "
      "they are recorded in /samples/status. `treedyn-ensemble merge -o OUT.h5 PART ...` joins the parts of "
      "--samples runs.");
  app.add_option("JOB", c.options.job_path, "job file (TOML) with an [ensemble] section")->required();
  app.add_option("-o,--output", c.options.output_path,
                 "output file (HDF5), written atomically (required unless --check)");
  app.add_flag("--check", c.check_only,
               "validate the job and its [ensemble], print the model and the ensemble and how many ranks it can keep "
               "busy (timing its nominal run and sample 0, and writing 16 MiB to a file without a name in "
               "--output's directory, or the current one); leaves nothing behind");
  app.add_flag("-q,--quiet", c.options.quiet, "no progress and no summary");
  c.sample_option =
      app.add_option("--sample", c.sample,
                     "integrate sample K alone and write its full trajectory (treedyn run layout, with "
                     "/sample/inputs) to --output; its final state is bitwise the ensemble's /samples/final_state[K]");
  c.write_job_option =
      app.add_option("--write-job", c.job_sample,
                     "write sample K as a standalone job file to --output (the job without [ensemble], plus a "
                     "[sample] section with its inputs); treedyn run of it reproduces the sample");
  for (auto* o : {c.sample_option, c.write_job_option}) o->check(CLI::NonNegativeNumber)->excludes("--check");
  c.sample_option->excludes(c.write_job_option);
  app.add_option("--from", c.from,
                 "with --sample or --write-job: the job's ensemble file (HDF5); needed for a run whose "
                 "inputs follow from the runs before it (a subset simulation's level after 0)")
      ->excludes("--check");
  app.add_option("--checkpoint-every", c.options.checkpoint_every,
                 "seconds between each rank's checkpoint in OUTPUT.checkpoint/ (0: no checkpoints); "
                 "a stop signal writes one and exits 5")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--resume", c.options.resume,
               "continue from OUTPUT.checkpoint/ (any number of ranks); the result is bitwise that of an "
               "uninterrupted run. Without a checkpoint it starts from the beginning");
  c.samples_option = app.add_option(
      "--samples", c.sample_range,
      "FIRST:END: run only the sample indices FIRST .. END-1 and write a part file to --output (not HDF5); "
      "`treedyn-ensemble merge -o OUT.h5 PART ...` joins the parts (e.g. of a Slurm array job)");
  c.samples_option->excludes(c.sample_option)->excludes(c.write_job_option);
  app.add_option("--progress-interval", c.options.progress_interval,
                 "seconds between progress lines when stderr is not a terminal")
      ->check(CLI::PositiveNumber);
  // The tests' seam (parallel/test_hooks.hpp), left out of --help.
  app.add_option("--test-hold-after", c.options.test.hold_after)->group("");
  app.add_flag("--test-hold-unsaved", c.options.test.hold_unsaved)->group("");
  app.add_option("--test-unit-rows", c.options.test.unit_rows)->group("");
}

// --samples FIRST:END into the options; false (and a message on rank 0) when malformed.
bool read_sample_range(const std::string& range, treedyn::parallel::EnsembleOptions& options, int rank) {
  const std::size_t colon = range.find(':');
  const std::string a = range.substr(0, colon), b = colon == std::string::npos ? "" : range.substr(colon + 1);
  char* rest = nullptr;
  const unsigned long long first = std::strtoull(a.c_str(), &rest, 10);
  const bool first_ok = !a.empty() && *rest == '\0' && a.find('-') == std::string::npos;
  const unsigned long long end = std::strtoull(b.c_str(), &rest, 10);
  const bool end_ok = !b.empty() && *rest == '\0' && b.find('-') == std::string::npos;
  if (!first_ok || !end_ok || first >= end) {
    if (rank == 0)
      std::cerr << "error: --samples " << range
                << ": give FIRST:END, two sample indices with FIRST < END (END is not included)\n";
    return false;
  }
  options.first_sample = first;
  options.end_sample = end;
  return true;
}

// One sample on its own is serial: rank 0 does it, every rank returns its code.
int one_sample(const CommandLine& c, int rank) {
  using namespace treedyn;
  int code = kExitOk;
  if (rank == 0)
    code = *c.sample_option ? rerun_sample(c.options.job_path, static_cast<std::uint64_t>(c.sample),
                                           c.options.output_path, c.options.quiet, c.options.provenance, c.from)
                            : write_sample_job(c.options.job_path, static_cast<std::uint64_t>(c.job_sample),
                                               c.options.output_path, c.from);
  MPI_Bcast(&code, 1, MPI_INT, 0, MPI_COMM_WORLD);
  return code;
}

// Slurm asked for several tasks but MPI sees one rank (a plain `srun` of a
// binary started without PMI, say): each task would run the whole ensemble
// and race to rename the same output. Refused before any work.
bool started_without_pmi(const treedyn::parallel::Session& session, const std::string& output) {
  const char* tasks = std::getenv("SLURM_NTASKS");
  if (!tasks || session.size() != 1 || std::atol(tasks) <= 1) return false;
  std::cerr << "error: SLURM_NTASKS=" << tasks << " but MPI sees 1 rank: every task would run the whole ensemble and "
            << "race to write " << output
            << ". Start it with `srun --mpi=pmix` or `mpirun` inside the allocation (jobs/slurm_ensemble.sh)\n";
  return true;
}

// An srun task (SLURM_PROCID and SLURM_STEP_NUM_TASKS: a job step, not the
// batch script, whose environment has SLURM_NTASKS only) of a step of several
// tasks with no process manager interface in its environment (`srun
// --mpi=none`, or a cluster whose default is none): MPI_Init would fail there
// with a bare "internal error". Refused before it, by task 0 in words; every
// task exits 2. --check, --help and merge need no ranks and are let through.
bool srun_task_without_pmi(int argc, char** argv) {
  const char* task = std::getenv("SLURM_PROCID");
  const char* tasks = std::getenv("SLURM_STEP_NUM_TASKS");
  if (!task || !tasks || std::atol(tasks) <= 1) return false;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--check" || a == "--help" || a == "-h" || (k == 1 && a == "merge")) return false;
  }
  for (const char* pmi : {"PMIX_RANK", "PMI_RANK", "PMI_FD", "OMPI_COMM_WORLD_RANK"})
    if (std::getenv(pmi)) return false;
  if (std::atol(task) == 0)
    std::cerr << "error: started by srun as one of " << tasks
              << " tasks without a process manager interface (no PMIX_RANK or PMI_RANK: srun --mpi=none?), so "
                 "MPI cannot join the tasks. Start it with `srun --mpi=pmix` (see `srun --mpi=list`) or `mpirun` "
                 "inside the allocation (jobs/slurm_ensemble.sh)\n";
  return true;
}

int run(const CommandLine& c, const treedyn::parallel::Session& session) {
  using namespace treedyn;
  try {
    return parallel::run_ensemble(MPI_COMM_WORLD, c.options);
  } catch (const std::bad_alloc&) {
    std::cerr << "error: out of memory on rank " << session.rank()
              << ": the job asks for more than this node (or its memory limit) gives; use fewer ranks per node, "
                 "fewer histogram_bins, output times or quantities\n";
    return end_all(session, kExitMemory);
  } catch (const std::exception& e) {
    std::cerr << "internal error on rank " << session.rank() << ": " << e.what() << "\n";
    return end_all(session, kExitInternal);
  }
}

}  // namespace

int main(int argc, char** argv) {
  using namespace treedyn;
  // Before MPI_Init: MPI's threads must inherit the blocked signals.
  process::start_signal_owner();
  h5::quiet_errors();  // first of all HDF5 calls: no exit handler, no error stack on stderr
  if (srun_task_without_pmi(argc, argv)) return kExitBadInput;
  parallel::Session session(&argc, &argv);
  if (argc > 1 && std::string(argv[1]) == "merge") {
    int code = merge_command(argc - 1, argv + 1, session.rank());
    MPI_Bcast(&code, 1, MPI_INT, 0, MPI_COMM_WORLD);
    return code;
  }
  CLI::App app{"treedyn-ensemble: perturbed runs of one treedyn job across MPI ranks, with statistics in HDF5"};
  CommandLine c;
  define_options(app, c);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = session.rank() == 0 ? app.exit(e) : (e.get_exit_code() == 0 ? 0 : 1);
    return code == 0 ? kExitOk : kExitBadInput;
  }
  if (c.check_only) return session.rank() == 0 ? check(c.options.job_path, c.options.output_path) : kExitOk;
  if (*c.samples_option && !read_sample_range(c.sample_range, c.options, session.rank())) return kExitBadInput;
  c.options.provenance = h5::start_provenance(argc, argv, c.options.job_path);
  if (c.options.output_path.empty()) {
    if (session.rank() == 0) std::cerr << "error: --output is required (or use --check)\n";
    return kExitBadInput;
  }
  if (!c.from.empty() && !*c.sample_option && !*c.write_job_option) {
    if (session.rank() == 0) std::cerr << "error: --from is only for --sample K or --write-job K\n";
    return kExitBadInput;
  }
  if (*c.sample_option || *c.write_job_option) return one_sample(c, session.rank());
  if (started_without_pmi(session, c.options.output_path)) return kExitBadInput;
  return run(c, session);
}
