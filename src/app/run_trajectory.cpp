#include "app/run_trajectory.hpp"

#include <chrono>
#include <iostream>
#include <optional>
#include <string>

#include "app/model_summary.hpp"
#include "common/exit_codes.hpp"
#include "common/format.hpp"
#include "output/recorder.hpp"
#include "process/atomic_file.hpp"

namespace treedyn {

int run_trajectory(const Job& job, const Model& model, const InitialState& initial, const std::string& output_path,
                   bool quiet, const h5::RunProvenance& run, const h5::SampleOrigin* sample) {
  process::check_output_path(output_path);  // refuse before integrating, not after
  Recorder recorder(model, job.output, EnergyTracking::on);
  const OutputSpec motion_spec = motion_output();
  Recorder motion(model, motion_spec);  // /motion, for the viewers
  SimulationRequest request = job.request;
  request.accelerations_at_outputs = recorder.needs_accelerations();
  const auto start = std::chrono::steady_clock::now();
  const IntegrationOutcome outcome = simulate(model, initial, request, [&](const Model& m, const Data& d) {
    recorder.record(m, d);
    motion.record(m, d);
  });
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!outcome.ok() && !sample) {
    std::cerr << job.file << ": integration failed (" << name(outcome.failure) << ") at t = " << outcome.time_reached
              << " s after " << outcome.stats.steps << " steps";
    if (!outcome.message.empty()) std::cerr << ": " << outcome.message;
    std::cerr << "\nno output written. Loosen the tolerances, raise [integrator] max_steps, or "
                 "check the model.\n";
    return kExitIntegration;
  }
  // A rerun ensemble sample is marked as the ensemble records it: how far it
  // got and, when it failed (what the user came to see), status 1 and why.
  std::optional<h5::SampleOrigin> origin;
  if (sample) {
    origin = *sample;
    origin->time_reached = outcome.time_reached;
    if (!outcome.ok()) {
      origin->status = 1;
      origin->reason = failure_reason(outcome);
    }
  }
  const MotionScene scene = motion_scene(job.definition, model);
  h5::write_trajectory(output_path, job, recorder, outcome, run, {scene, motion}, origin ? &*origin : nullptr);
  if (!outcome.ok()) {
    std::cout << "sample " << sample->index << " fails as in the ensemble: " << origin->reason << "\nwrote "
              << output_path << " (the " << recorder.times().size()
              << " output times before the failure; /sample status 1)\n";
    return kExitOk;
  }
  if (!quiet) print_run_summary(std::cout, job, recorder, outcome, wall);
  std::cout << "wrote " << output_path << " (" << recorder.times().size() << " output times)\n";
  return kExitOk;
}

}  // namespace treedyn
