// Integrates one ensemble sample (or the nominal run) and reduces its
// trajectory to what the ensemble keeps. A sample is a parameter vector and
// an initial state: the nominal ones with the sample's perturbations applied.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "ensemble/ensemble_spec.hpp"
#include "integrate/settings.hpp"
#include "job/job.hpp"
#include "model/initial_state.hpp"
#include "model/model.hpp"
#include "output/recorder.hpp"

namespace treedyn::ensemble {

enum class SampleStatus : std::int32_t {
  ok = 0,
  integration_failed = 1,  // the integrator gave up: reason and time reached recorded
  invalid_model = 2,       // the perturbed inputs gave an invalid model (e.g. negative mass)
  not_run = 3,             // a merge of an incomplete set of parts: no part held this sample
};

struct SampleRecord {
  std::uint64_t index = 0;
  SampleStatus status = SampleStatus::ok;
  std::string reason;                // empty when ok
  double time_reached = 0.0;
  IntegratorStats stats;
  std::vector<double> inputs;        // the sampled input values, SI
  std::vector<double> reductions;    // per spec.per_sample reduction, one per column (NaN when failed)
  std::vector<double> responses;     // per spec.responses (NaN when failed)
  std::vector<double> final_state;   // output/final_state.hpp; NaN when failed
  std::vector<double> trajectory;    // times x columns, only for samples < store_trajectories
};

class SampleRunner {
 public:
  SampleRunner(const Job& job, const EnsembleSpec& spec);

  const ColumnLayout& layout() const { return recorder_.layout(); }
  std::size_t times() const { return job_.request.output_times.size(); }
  std::size_t final_state_size() const;

  // Sample k, perturbed as the spec says; `nominal` skips the perturbations.
  // On success `trajectory` holds times x columns values (row-major).
  // `between_outputs`, if given, is called at every output time (the MPI
  // driver keeps communication going with it).
  SampleRecord run(std::uint64_t k, bool nominal, std::vector<double>& trajectory,
                   const std::function<void()>& between_outputs = {});

  // The record of a sample that produced nothing: NaN reductions, responses and final state.
  SampleRecord failed_record(std::uint64_t k, SampleStatus status, std::string reason) const;

  // The per-sample set-up on its own: sample k's parameter vector and
  // initial state (the nominal ones for `nominal`), and the model derived
  // from them. Returns the sampled inputs; throws ModelError when the
  // perturbed parameters make an invalid model.
  std::vector<double> prepare(std::uint64_t k, bool nominal);
  const Model& model() const { return model_; }
  const InitialState& initial_state() const { return state_; }

  // The sampled values (SI) of sample k's perturbed inputs.
  std::vector<double> sample_inputs(std::uint64_t k);

 private:
  // parameters_ and state_: the nominal ones with `inputs` applied (none:
  // nominal), then model_. Throws ModelError.
  void set_up(const std::vector<double>& inputs);

  const Job& job_;
  const EnsembleSpec& spec_;
  SampleDesign design_;
  std::vector<double> uniforms_;
  std::vector<double> parameters_;  // this sample's parameter vector
  InitialState state_;              // this sample's initial state
  Model model_;                     // derived from parameters_ (storage reused)
  Recorder recorder_;
};

}  // namespace treedyn::ensemble
