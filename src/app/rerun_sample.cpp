#include "app/rerun_sample.hpp"

#include <iostream>

#include "app/command_errors.hpp"
#include "app/exit_codes.hpp"
#include "app/run_trajectory.hpp"
#include "common/error.hpp"
#include "job/ensemble_spec.hpp"
#include "job/sample_job.hpp"
#include "ensemble/sample_runner.hpp"
#include "process/atomic_file.hpp"
#include "job/job_error.hpp"

namespace treedyn {
namespace {

// Sample k must exist: the message says how many there are.
void require_sample(const Job& job, const ensemble::EnsembleSpec& spec, std::uint64_t k) {
  if (k >= spec.samples)
    throw JobError(job.file, 0, 0, "ensemble.samples",
                   "there is no sample " + std::to_string(k) + ": the ensemble has " +
                       std::to_string(spec.samples) + " samples, 0 .. " +
                       std::to_string(spec.samples - 1) +
                       (spec.design == ensemble::Design::saltelli ? " (saltelli: samples x (D + 2) runs)" : ""));
}

}  // namespace

int rerun_sample(const std::string& job_path, std::uint64_t k, const std::string& output_path,
                 bool quiet, const RunProvenance& run) {
  return exit_code_of([&]() -> int {
    const auto [job, spec] = ensemble::read_ensemble_job(JobDocument::read(job_path));
    require_sample(job, spec, k);
    ensemble::SampleRunner runner(job, spec);
    SampleOrigin origin;
    origin.index = k;
    origin.input_names = spec.input_names();
    origin.input_units = spec.input_units();
    try {
      origin.inputs = runner.prepare(k, false);
    } catch (const ModelError& e) {
      std::cerr << job_path << ", sample " << k << ": the sampled inputs give an invalid model: "
                << e.what() << "\n(the ensemble records this sample with status 2); no output written\n";
      return kExitIntegration;
    }
    return run_trajectory(job, runner.model(), runner.initial_state(), output_path, quiet, run, &origin);
  });
}

int write_sample_job(const std::string& job_path, std::uint64_t k, const std::string& output_path) {
  return exit_code_of([&]() -> int {
    const auto [job, spec] = ensemble::read_ensemble_job(JobDocument::read(job_path));
    ensemble::require_not_a_sample_job(job);
    require_sample(job, spec, k);
    ensemble::SampleRunner runner(job, spec);
    const std::vector<double> inputs = runner.sample_inputs(k);
    process::write_file_atomically(output_path, ensemble::sample_job_text(job, spec, k, inputs));
    std::cout << "wrote " << output_path << " (sample " << k << " of " << job_path
              << "; run it with treedyn run)\n";
    return kExitOk;
  });
}

}  // namespace treedyn
