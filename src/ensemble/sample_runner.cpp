#include "ensemble/sample_runner.hpp"

#include <algorithm>
#include <limits>

#include "common/error.hpp"
#include "common/format.hpp"
#include "designs/design_rules.hpp"
#include "integrate/simulate.hpp"
#include "model/definition.hpp"
#include "output/final_state.hpp"

namespace treedyn::ensemble {

SampleRunner::SampleRunner(const Job& job, const EnsembleSpec& spec)
    : job_(job),
      spec_(spec),
      design_(spec.design, spec.seed, spec.runs, spec.input_dimensions(), spec.unit_of_input(), spec.morris),
      copula_(spec.input_dimensions(), spec.correlations),
      uniforms_(spec.input_dimensions()),
      recorder_(job.model, job.output),
      request_(job.request) {
  request_.accelerations_at_outputs = recorder_.needs_accelerations();
}

std::size_t SampleRunner::final_state_size() const {
  return kFinalStatePerBody * static_cast<std::size_t>(job_.model.n);
}

SampleRecord SampleRunner::failed_record(std::uint64_t k, SampleStatus status, std::string reason) const {
  SampleRecord record;
  record.index = k;
  record.status = status;
  record.reason = std::move(reason);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  record.reductions.assign(spec_.per_sample.size() * layout().columns, nan);
  record.responses.assign(spec_.responses.size(), nan);
  record.final_state.assign(final_state_size(), std::numeric_limits<double>::quiet_NaN());
  return record;
}

std::vector<double> SampleRunner::sample_inputs(std::uint64_t k) {
  design_.point(k, uniforms_);
  return inputs_at(uniforms_);
}

std::vector<double> SampleRunner::inputs_at(std::span<const double> uniforms) const {
  std::vector<double> u(uniforms.begin(), uniforms.end());
  if (!copula_.empty()) copula_.correlate(u);
  std::vector<double> inputs(u.size());
  std::size_t d = 0;
  for (const sampling::Perturbation& p : spec_.perturbations) {
    const auto n = static_cast<std::size_t>(p.dimensions());
    p.sample(std::span<const double>(u).subspan(d, n), std::span<double>(inputs).subspan(d, n));
    d += n;
  }
  return inputs;
}

void SampleRunner::set_up(const std::vector<double>& inputs) {
  const auto p0 = job_.definition.parameters.nominal();
  parameters_.assign(p0.begin(), p0.end());
  state_ = job_.initial;
  if (!inputs.empty()) sampling::apply_inputs(spec_.perturbations, inputs, job_.initial, parameters_, state_);
  derive_model(job_.definition, parameters_, model_);
}

std::vector<double> SampleRunner::prepare(std::uint64_t k, bool nominal) {
  std::vector<double> inputs;
  if (!nominal) inputs = sample_inputs(k);
  set_up(inputs);
  return inputs;
}

SampleRecord SampleRunner::run(std::uint64_t k, bool nominal, std::vector<double>& trajectory,
                               const std::function<void()>& between_outputs) {
  std::vector<double> inputs;
  if (!nominal) inputs = sample_inputs(k);
  return run_inputs(k, std::move(inputs), nominal, trajectory, between_outputs);
}

SampleRecord SampleRunner::run_at(std::uint64_t k, std::span<const double> uniforms, std::vector<double>& trajectory,
                                  const std::function<void()>& between_outputs) {
  return run_inputs(k, inputs_at(uniforms), false, trajectory, between_outputs);
}

SampleRecord SampleRunner::run_inputs(std::uint64_t k, std::vector<double> inputs, bool nominal,
                                      std::vector<double>& trajectory, const std::function<void()>& between_outputs) {
  try {
    set_up(inputs);
  } catch (const ModelError& e) {
    SampleRecord record = failed_record(k, SampleStatus::invalid_model, e.what());
    record.inputs = std::move(inputs);
    return record;
  }

  recorder_.clear();
  const IntegrationOutcome outcome = simulate(model_, state_, request_, [&](const Model& m, const Data& data) {
    recorder_.record(m, data);
    if (between_outputs) between_outputs();
  });
  if (!outcome.ok()) {
    // Nothing of a run that did not finish is kept: NaN maxima and final state.
    SampleRecord failed = failed_record(k, SampleStatus::integration_failed, failure_reason(outcome));
    failed.inputs = std::move(inputs);
    failed.stats = outcome.stats;
    failed.time_reached = outcome.time_reached;
    return failed;
  }
  SampleRecord record;
  record.index = k;
  record.inputs = std::move(inputs);
  record.stats = outcome.stats;
  record.time_reached = outcome.time_reached;
  recorder_.swap_values(trajectory);
  const std::size_t columns = layout().columns;
  const std::vector<double>& times = recorder_.times();
  reduce_columns(trajectory, times, columns, spec_.per_sample, record.reductions, reduction_scratch_);
  record.responses.reserve(spec_.responses.size());  // one allocation, however many responses
  for (const Response& response : spec_.responses)
    record.responses.push_back(evaluate(response, trajectory, times, columns));
  if (!nominal && k < spec_.store_trajectories) record.trajectory = trajectory;
  record.final_state.resize(final_state_size());
  write_final_state(recorder_.last(), record.final_state);  // the state at the last output time
  return record;
}

persistence::RecordShape record_shape(const SampleRunner& runner, std::uint64_t first, std::uint64_t end) {
  const EnsembleSpec& spec = runner.spec();
  persistence::RecordShape shape;
  shape.first = first;
  shape.end = end;
  shape.inputs = spec.input_dimensions();
  shape.reductions = spec.per_sample.size() * runner.layout().columns;
  shape.responses = spec.responses.size();
  shape.final_state = runner.final_state_size();
  shape.trajectory = runner.times() * runner.layout().columns;
  shape.stored = spec.store_trajectories;
  // /stats: the runs the answers count (subset simulation: level 0).
  shape.statistics_end = designs::rules_of(spec.design).answered_runs(spec, shape.statistics_end);
  return shape;
}

persistence::StatisticsShape statistics_shape(const SampleRunner& runner) {
  return {runner.times(), runner.layout().columns, runner.spec().histogram_bins};
}

}  // namespace treedyn::ensemble
