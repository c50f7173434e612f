#include "ensemble/sample_runner.hpp"

#include <algorithm>
#include <limits>

#include "common/error.hpp"
#include "dynamics/recovered.hpp"
#include "integrate/simulate.hpp"
#include "job/toml_view.hpp"
#include "output/quantities.hpp"

namespace treedyn::ensemble {

ColumnLayout column_layout(const Job& job) {
  ColumnLayout l;
  for (const std::string& q : job.output.quantities) {
    l.quantity.push_back(q);
    l.info.push_back(find_quantity(q));
    l.offset.push_back(l.columns);
    l.names.push_back(quantity_columns(q, job.model, job.output));
    l.columns += l.names.back().size();
  }
  return l;
}

SampleRunner::SampleRunner(const Job& job, const EnsembleSpec& spec)
    : job_(job),
      spec_(spec),
      design_(spec.design, spec.seed, spec.samples, spec.input_dimensions()),
      layout_(column_layout(job)),
      uniforms_(spec.input_dimensions()) {}

SampleRecord SampleRunner::failed_record(std::uint64_t k, SampleStatus status,
                                         std::string reason) const {
  SampleRecord record;
  record.index = k;
  record.status = status;
  record.reason = std::move(reason);
  record.max_over_time.assign(layout_.columns, std::numeric_limits<double>::quiet_NaN());
  record.final_state.assign(final_state_size(), std::numeric_limits<double>::quiet_NaN());
  return record;
}

SampleRecord SampleRunner::run(std::uint64_t k, bool nominal, std::vector<double>& trajectory,
                               const std::function<void()>& between_outputs) {
  ModelSpec spec = job_.model.spec;
  SimulationRequest request = job_.request;
  std::vector<double> inputs;
  if (!nominal) {
    design_.point(k, uniforms_);
    inputs.resize(uniforms_.size());
    std::vector<std::size_t> first(spec_.perturbations.size());
    std::size_t d = 0;
    for (std::size_t p = 0; p < spec_.perturbations.size(); ++p) {
      const Perturbation& pert = spec_.perturbations[p];
      const auto n = static_cast<std::size_t>(pert.dimensions());
      first[p] = d;
      pert.sample(std::span<const double>(uniforms_).subspan(d, n), std::span<double>(inputs).subspan(d, n));
      d += n;
    }
    auto apply = [&](bool angular_velocity) {
      for (std::size_t p = 0; p < spec_.perturbations.size(); ++p) {
        const Perturbation& pert = spec_.perturbations[p];
        if ((pert.field == Perturbation::Field::angular_velocity) != angular_velocity) continue;
        pert.apply(std::span<const double>(inputs).subspan(first[p], static_cast<std::size_t>(pert.dimensions())),
                   spec, request.initial);
      }
    };
    apply(false);
    // A spin the job gave in a body's own frame turns with the body: the
    // reader's own expression with the perturbed orientation (bitwise the
    // nominal value when the orientation is unchanged). Angular-velocity
    // perturbations, in inertial components, come after.
    for (std::size_t u = 0; u < job_.spin_in_body_frame.size(); ++u)
      if (const auto& body = job_.spin_in_body_frame[u]; body && request.initial.rotation[u] != job_.request.initial.rotation[u])
        request.initial.angular_velocity[u] = request.initial.rotation[u] * *body;
    apply(true);
  }

  Model model;
  try {
    model = build_model(spec);
  } catch (const ModelError& e) {
    SampleRecord record = failed_record(k, SampleStatus::invalid_model, e.what());
    record.inputs = std::move(inputs);
    return record;
  }

  SampleRecord record;
  record.index = k;
  record.inputs = std::move(inputs);
  record.max_over_time.assign(layout_.columns, -std::numeric_limits<double>::infinity());
  trajectory.clear();
  trajectory.reserve(times() * layout_.columns);
  const IntegrationOutcome outcome =
      simulate(model, request, [&](const Model& m, const Data& data) {  // each output time
        recover(m, data, state_);
        row_.clear();
        for (const QuantityInfo* q : layout_.info) q->extract(state_, job_.output, row_);
        for (std::size_t c = 0; c < row_.size(); ++c)
          record.max_over_time[c] = std::max(record.max_over_time[c], row_[c]);
        trajectory.insert(trajectory.end(), row_.begin(), row_.end());
        if (between_outputs) between_outputs();
      });
  record.stats = outcome.stats;
  record.time_reached = outcome.time_reached;
  if (!outcome.ok()) {
    // Nothing of a run that did not finish is kept: NaN maxima and final state.
    SampleRecord failed = failed_record(
        k, SampleStatus::integration_failed,
        std::string(name(outcome.failure)) + " at t = " + format_number(outcome.time_reached) +
            " s" + (outcome.message.empty() ? "" : ": " + outcome.message));
    failed.inputs = std::move(record.inputs);
    failed.stats = outcome.stats;
    failed.time_reached = outcome.time_reached;
    return failed;
  }
  // The state at the last output time is still in state_.
  record.final_state.resize(final_state_size());
  for (int u = 0; u < model.n; ++u) {
    Quat q(state_.rotation[u]);
    if (q.w() < 0.0) q.coeffs() *= -1.0;
    const Vec3& w = state_.angular_velocity[u];
    double* out = record.final_state.data() + 7 * u;
    out[0] = q.w(), out[1] = q.x(), out[2] = q.y(), out[3] = q.z();
    out[4] = w.x(), out[5] = w.y(), out[6] = w.z();
  }
  return record;
}

}  // namespace treedyn::ensemble
