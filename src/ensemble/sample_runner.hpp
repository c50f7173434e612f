// Integrates one ensemble sample (or the nominal run) and reduces its
// trajectory to what the ensemble keeps. A sample is a parameter vector and
// an initial state: the nominal ones with the sample's perturbations applied.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "designs/sample_design.hpp"
#include "integrate/settings.hpp"
#include "job/ensemble_spec.hpp"
#include "job/job.hpp"
#include "model/initial_state.hpp"
#include "model/model.hpp"
#include "output/recorder.hpp"
#include "output/response.hpp"
#include "output/sample_record.hpp"
#include "persistence/checkpoint.hpp"

namespace treedyn::ensemble {

// Thrown by a between_outputs callback to give up the sample in flight (a
// stop signal): run() lets it through, and nothing of the sample is kept.
struct SampleAbandoned {};

class SampleRunner {
 public:
  SampleRunner(const Job& job, const EnsembleSpec& spec);

  const ColumnLayout& layout() const { return recorder_.layout(); }
  const EnsembleSpec& spec() const { return spec_; }
  std::size_t times() const { return job_.request.output_times.size(); }
  std::size_t final_state_size() const;

  // Sample k, perturbed as the spec says; `nominal` skips the perturbations.
  // On success `trajectory` holds times x columns values (row-major).
  // `between_outputs`, if given, is called at every output time (the MPI
  // driver keeps communication going with it, and may throw SampleAbandoned).
  SampleRecord run(std::uint64_t k, bool nominal, std::vector<double>& trajectory,
                   const std::function<void()>& between_outputs = {});

  // Run k at explicit uniform numbers in (0, 1), one per input dimension,
  // instead of the design's (subset simulation's chains make their own).
  SampleRecord run_at(std::uint64_t k, std::span<const double> uniforms, std::vector<double>& trajectory,
                      const std::function<void()>& between_outputs = {});

  // The record of a sample that produced nothing: NaN reductions, responses and final state.
  SampleRecord failed_record(std::uint64_t k, SampleStatus status, std::string reason) const;

  // The per-sample set-up on its own: sample k's parameter vector and
  // initial state (the nominal ones for `nominal`), and the model derived
  // from them. Returns the sampled inputs; throws ModelError when the
  // perturbed parameters make an invalid model.
  std::vector<double> prepare(std::uint64_t k, bool nominal);
  // The same with given inputs (a run whose inputs are not the design's).
  void prepare_inputs(const std::vector<double>& inputs) { set_up(inputs); }
  const Model& model() const { return model_; }
  const InitialState& initial_state() const { return state_; }

  // The sampled values (SI) of sample k's perturbed inputs.
  std::vector<double> sample_inputs(std::uint64_t k);
  // ... of the inputs at independent uniform numbers `uniforms` (one per
  // dimension; correlated inputs go through the normal copula first).
  std::vector<double> inputs_at(std::span<const double> uniforms) const;

 private:
  // parameters_ and state_: the nominal ones with `inputs` applied (none:
  // nominal), then model_. Throws ModelError.
  void set_up(const std::vector<double>& inputs);
  SampleRecord run_inputs(std::uint64_t k, std::vector<double> inputs, bool nominal, std::vector<double>& trajectory,
                          const std::function<void()>& between_outputs);

  const Job& job_;
  const EnsembleSpec& spec_;
  designs::SampleDesign design_;
  sampling::NormalCopula copula_;  // the correlated inputs ([[ensemble.correlation]])
  std::vector<double> uniforms_;
  std::vector<double> parameters_;  // this sample's parameter vector
  InitialState state_;              // this sample's initial state
  Model model_;                     // derived from parameters_ (storage reused)
  Recorder recorder_;
  ReductionScratch reduction_scratch_;  // reused by every sample's reductions
  SimulationRequest request_;           // the job's, with what recorder_ needs at output times
};

// The shape every record and the statistics of this job have (what a
// checkpoint or part file must match to be loaded).
persistence::RecordShape record_shape(const SampleRunner& runner, std::uint64_t first, std::uint64_t end);
persistence::StatisticsShape statistics_shape(const SampleRunner& runner);

}  // namespace treedyn::ensemble
