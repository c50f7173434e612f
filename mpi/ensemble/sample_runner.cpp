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

SampleRecord SampleRunner::run(std::uint64_t k, bool nominal, std::vector<double>& trajectory) {
  SampleRecord record;
  record.index = k;
  ModelSpec spec = job_.model.spec;
  SimulationRequest request = job_.request;
  if (!nominal) {
    design_.point(k, uniforms_);
    record.inputs.resize(uniforms_.size());
    std::size_t d = 0;
    for (const Perturbation& p : spec_.perturbations) {
      const auto n = static_cast<std::size_t>(p.dimensions());
      p.sample(std::span<const double>(uniforms_).subspan(d, n),
               std::span<double>(record.inputs).subspan(d, n));
      p.apply(std::span<const double>(record.inputs).subspan(d, n), spec, request.initial);
      d += n;
    }
  }
  record.max_over_time.assign(layout_.columns, -std::numeric_limits<double>::infinity());
  record.final_state.assign(final_state_size(), std::numeric_limits<double>::quiet_NaN());

  Model model;
  try {
    model = build_model(spec);
  } catch (const ModelError& e) {
    record.status = SampleStatus::invalid_model;
    record.reason = e.what();
    return record;
  }

  trajectory.clear();
  trajectory.reserve(times() * layout_.columns);
  const IntegrationOutcome outcome =
      simulate(model, request, [&](const Model& m, const Data& data) {
        const Recovered state = recover(m, data);
        row_.clear();
        for (const std::string& q : layout_.quantity) extract_quantity(q, m, job_.output, state, row_);
        for (std::size_t c = 0; c < row_.size(); ++c)
          record.max_over_time[c] = std::max(record.max_over_time[c], row_[c]);
        trajectory.insert(trajectory.end(), row_.begin(), row_.end());
        for (int u = 0; u < m.n; ++u) {  // kept from the last output time
          Quat q(state.rotation[u]);
          if (q.w() < 0.0) q.coeffs() *= -1.0;
          const Vec3& w = state.angular_velocity[u];
          double* out = record.final_state.data() + 7 * u;
          out[0] = q.w(), out[1] = q.x(), out[2] = q.y(), out[3] = q.z();
          out[4] = w.x(), out[5] = w.y(), out[6] = w.z();
        }
      });
  record.stats = outcome.stats;
  record.time_reached = outcome.time_reached;
  if (!outcome.ok()) {
    record.status = SampleStatus::integration_failed;
    record.reason = std::string(name(outcome.failure)) + " at t = " +
                    format_number(outcome.time_reached) + " s" +
                    (outcome.message.empty() ? "" : ": " + outcome.message);
    // The documented meaning: no final state for a run that did not finish.
    std::fill(record.final_state.begin(), record.final_state.end(),
              std::numeric_limits<double>::quiet_NaN());
  }
  return record;
}

}  // namespace treedyn::ensemble
