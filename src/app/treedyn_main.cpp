// The `treedyn` command: check a job, run one trajectory into HDF5.
#include <CLI/CLI.hpp>

#include <cstdint>
#include <iostream>

#include "app/command_errors.hpp"
#include "app/model_summary.hpp"
#include "app/report_command.hpp"
#include "app/run_trajectory.hpp"
#include "common/exit_codes.hpp"
#include "hdf5/hdf5.hpp"
#include "job/job.hpp"
#include "job/sample_job.hpp"
#include "process/signals.hpp"

namespace treedyn {
namespace {

// The whole job is checked, [ensemble] included when there is one (its
// summary is treedyn-ensemble --check's).
int check_command(const std::string& job_path, bool all_parameters) {
  const JobDocument document = JobDocument::read(job_path);
  const Job job = read_sample_job(document);
  const bool ensemble = document.has("ensemble");
  if (ensemble) read_ensemble(job);
  print_model_summary(std::cout, job);
  print_parameters(std::cout, job.definition.parameters, all_parameters ? SIZE_MAX : 40);
  if (ensemble) std::cout << "[ensemble]: checked too (treedyn-ensemble --check prints what it samples)\n";
  std::cout << job_path << ": OK\n";
  return kExitOk;
}

int run_command(const std::string& job_path, const std::string& output_path, bool quiet, const h5::RunProvenance& run) {
  const Job job = read_sample_job(JobDocument::read(job_path));
  return run_trajectory(job, job.model, job.initial, output_path, quiet, run);
}

}  // namespace
}  // namespace treedyn

int main(int argc, char** argv) {
  using namespace treedyn;
  process::start_signal_owner();  // before any other thread: a signal removes temporary files, then ends us
  h5::quiet_errors();             // first of all HDF5 calls: no exit handler, no error stack on stderr
  CLI::App app{"treedyn: dynamics of trees of rigid bodies joined by spherical joints"};
  app.set_version_flag("--version", std::string("treedyn ") + TREEDYN_VERSION);
  app.require_subcommand(1);
  app.footer(
      "Exit codes: 0 ok, 1 internal error, 2 bad input (job file or command line), "
      "3 integration failure, 4 output (I/O) failure, 5 interrupted (treedyn-ensemble, resumable with --resume; "
      "treedyn itself ends by the signal, its temporary file removed), 6 not enough memory.");

  std::string job_path, output_path;
  bool quiet = false;
  bool all_parameters = false;
  CLI::App* check =
      app.add_subcommand("check", "Validate a job file; print the model summary and its named parameters");
  check->add_option("JOB", job_path, "job file (TOML)")->required();
  check->add_flag("--parameters", all_parameters, "list every parameter (by default at most 40 are listed)");
  CLI::App* run = app.add_subcommand("run", "Integrate one trajectory and write it to HDF5");
  run->add_option("JOB", job_path, "job file (TOML)")->required();
  run->add_option("-o,--output", output_path, "output file (HDF5), written atomically")->required();
  run->add_flag("-q,--quiet", quiet, "print only the output file name");
  std::string report_file, report_dir;
  std::vector<std::string> report_quantities;
  CLI::App* report = app.add_subcommand(
      "report", "Draw a trajectory or ensemble file: DIR/index.html with PNG figures, and a text summary");
  report->add_option("FILE", report_file, "a file written by treedyn run or treedyn-ensemble")->required();
  report->add_option("-o,--output", report_dir, "report directory (default: FILE without .h5, plus _report)");
  report->add_option("--quantity", report_quantities,
                     "draw only these quantities (all of their column groups); repeatable");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitBadInput;
  }
  return exit_code_of([&]() -> int {
    if (*check) return check_command(job_path, all_parameters);
    if (*report) return report_command(report_file, report_dir, report_quantities);
    return run_command(job_path, output_path, quiet, h5::start_provenance(argc, argv, job_path));
  });
}
