#include "app/run_trajectory.hpp"

#include <chrono>
#include <string>
#include <iostream>

#include "app/exit_codes.hpp"
#include "app/model_summary.hpp"
#include "hdf5/hdf5.hpp"
#include "job/toml_view.hpp"
#include "output/recorder.hpp"

namespace treedyn {

int run_trajectory(const Job& job, const Model& model, const InitialState& initial,
                   const std::string& output_path, bool quiet, const RunProvenance& run,
                   const SampleOrigin* sample) {
  h5::check_output_path(output_path);  // refuse before integrating, not after
  Recorder recorder(model, job.output);
  const auto start = std::chrono::steady_clock::now();
  const IntegrationOutcome outcome = simulate(
      model, initial, job.request, [&](const Model& m, const Data& d) { recorder.record(m, d); });
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!outcome.ok() && sample) {
    // A failed ensemble sample is what the user came to see: its trajectory
    // up to the failure, marked as such (status 1, reason, time reached).
    SampleOrigin failed = *sample;
    failed.status = 1;
    // Worded as the ensemble's /samples/reason.
    failed.reason = std::string(name(outcome.failure)) + " at t = " + format_number(outcome.time_reached) +
                    " s" + (outcome.message.empty() ? "" : ": " + outcome.message);
    failed.time_reached = outcome.time_reached;
    write_trajectory(output_path, job, recorder, outcome, run, &failed);
    std::cout << "sample " << sample->index << " fails as in the ensemble: " << failed.reason << "\nwrote "
              << output_path << " (the " << recorder.times().size()
              << " output times before the failure; /sample status 1)\n";
    return kExitOk;
  }
  if (!outcome.ok()) {
    std::cerr << job.file << ": integration failed (" << name(outcome.failure) << ") at t = "
              << outcome.time_reached << " s after " << outcome.stats.steps << " steps";
    if (!outcome.message.empty()) std::cerr << ": " << outcome.message;
    std::cerr << "\nno output written. Loosen the tolerances, raise [integrator] max_steps, or "
                 "check the model.\n";
    return kExitIntegration;
  }
  write_trajectory(output_path, job, recorder, outcome, run, sample);
  if (!quiet) print_run_summary(std::cout, job, recorder, outcome, wall);
  std::cout << "wrote " << output_path << " (" << recorder.times().size() << " output times)\n";
  return kExitOk;
}

}  // namespace treedyn
