#include "app/rerun_sample.hpp"

#include <cmath>
#include <iostream>
#include <optional>

#include "app/command_errors.hpp"
#include "app/run_trajectory.hpp"
#include "common/error.hpp"
#include "common/exit_codes.hpp"
#include "designs/design_rules.hpp"
#include "designs/registry_analysis.hpp"
#include "ensemble/sample_runner.hpp"
#include "hdf5/read_file.hpp"
#include "job/ensemble_spec.hpp"
#include "job/job_error.hpp"
#include "job/sample_job.hpp"
#include "process/atomic_file.hpp"

namespace treedyn {
namespace {

// Sample k must exist: the message says how many there are.
void require_sample(const Job& job, const EnsembleSpec& spec, std::uint64_t k) {
  if (k >= spec.runs)
    throw JobError(job.file, 0, 0, "ensemble.samples",
                   "there is no sample " + std::to_string(k) + ": the ensemble has " + std::to_string(spec.runs) +
                       " samples, 0 .. " + std::to_string(spec.runs - 1) +
                       std::string(designs::rules_of(spec.design).runs_note()));
}

// Refused with what to do instead: a run that follows from the records
// before it needs the ensemble file, whose records replay it.
[[noreturn]] void refuse(const std::string& what) { throw CommandRefused(what); }

// Sample k's inputs: the design's, or, for a run that follows from the runs
// before it (a subset simulation's later level), those the design made,
// replayed from the ensemble file `from` (and checked against the inputs the
// file recorded for it).
std::vector<double> inputs_of(const Job& job, const EnsembleSpec& spec, ensemble::SampleRunner& runner, std::uint64_t k,
                              const std::string& from) {
  if (!designs::rules_of(spec.design).follows_records(spec, k)) return runner.sample_inputs(k);
  if (from.empty())
    refuse("run " + std::to_string(k) + " of this " + std::string(name(spec.design)) +
           " follows from the runs before it, not from the seed alone; give the ensemble's output file with "
           "--from FILE.h5");
  std::vector<double> inputs;
  std::optional<ensemble::ResponseTable> table;
  try {
    const h5::ReadFile file(from);
    if (!file.has_attribute("/", "job_text") || file.string_attribute("/", "job_text") != job.text)
      refuse("--from " + from + ": not an ensemble file of " + job.file + " (its job_text differs)");
    table = h5::response_table(file, spec.input_dimensions(), spec.responses.size());
    const std::optional<std::vector<double>> point = designs::replayed_point(spec, *table, k);
    if (!point)  // the rules and the registry disagree: a design's line is missing in registry_analysis.cpp
      throw std::logic_error("run " + std::to_string(k) + " follows from earlier records but has no replay");
    inputs = runner.inputs_at(*point);
  } catch (const h5::IoError& e) {
    refuse("--from " + from + ": " + e.what());
  } catch (const std::invalid_argument& e) {
    refuse("--from " + from + ": " + e.what());
  }
  for (std::size_t d = 0; d < inputs.size(); ++d)
    if (inputs[d] != table->input(k, d) && !(std::isnan(inputs[d]) && std::isnan(table->input(k, d))))
      refuse(from + ": the replayed inputs of run " + std::to_string(k) +
             " differ from those the file recorded "
             "(another build, or a file changed since)");
  return inputs;
}

}  // namespace

int rerun_sample(const std::string& job_path, std::uint64_t k, const std::string& output_path, bool quiet,
                 const h5::RunProvenance& run, const std::string& from) {
  return exit_code_of([&]() -> int {
    const auto [job, spec] = read_ensemble_job(JobDocument::read(job_path));
    require_sample(job, spec, k);
    ensemble::SampleRunner runner(job, spec);
    h5::SampleOrigin origin;
    origin.index = k;
    origin.input_names = spec.input_names();
    origin.input_units = spec.input_units();
    origin.inputs = inputs_of(job, spec, runner, k, from);
    try {
      runner.prepare_inputs(origin.inputs);
    } catch (const ModelError& e) {
      std::cerr << job_path << ", sample " << k << ": the sampled inputs give an invalid model: " << e.what()
                << "\n(the ensemble records this sample with status 2); no output written\n";
      return kExitIntegration;
    }
    return run_trajectory(job, runner.model(), runner.initial_state(), output_path, quiet, run, &origin);
  });
}

int write_sample_job(const std::string& job_path, std::uint64_t k, const std::string& output_path,
                     const std::string& from) {
  return exit_code_of([&]() -> int {
    const auto [job, spec] = read_ensemble_job(JobDocument::read(job_path));
    require_not_a_sample_job(job);
    require_sample(job, spec, k);
    ensemble::SampleRunner runner(job, spec);
    const std::vector<double> inputs = inputs_of(job, spec, runner, k, from);
    process::write_file_atomically(output_path, sample_job_text(job, spec, k, inputs));
    std::cout << "wrote " << output_path << " (sample " << k << " of " << job_path << "; run it with treedyn run)\n";
    return kExitOk;
  });
}

}  // namespace treedyn
