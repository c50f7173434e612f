#include "output/recorder.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace treedyn {

Recorder::Recorder(const Model& model, const OutputSpec& output, EnergyTracking energy)
    : output_(output),
      layout_(column_layout(model, output)),
      bodies_(model.n),
      parts_(layout_.needs | (energy == EnergyTracking::on ? kRecoverEnergy : 0u)) {}

void Recorder::clear() {
  times_.clear();
  values_.clear();
  max_energy_change_ = 0.0;
}

void Recorder::wrong_count(std::size_t written) const {
  throw std::logic_error("recorder: the quantities wrote " + std::to_string(written) + " values for the " +
                         std::to_string(layout_.columns) + " columns they name");
}

void Recorder::wrong_model(const Model& model) const {
  throw std::invalid_argument("recorder: a model of " + std::to_string(model.n) + " bodies, the columns are for " +
                              std::to_string(bodies_));
}

void Recorder::record(const Model& model, const Data& data) {
  if (model.n != bodies_) wrong_model(model);
  recover(model, data, state_, parts_);
  if (times_.empty()) first_energy_ = state_.energy;
  times_.push_back(state_.time);
  const std::size_t at = values_.size();
  values_.resize(at + layout_.columns);
  // Each quantity writes after the one before (the layout's order). A row
  // of another length would shift or overrun the trajectory: a programming
  // error (each quantity's own count is tested), stopped at its first row.
  double* const row = values_.data() + at;
  double* out = row;
  for (const QuantityInfo* q : layout_.info) out = q->extract(state_, output_, out);
  if (out != row + layout_.columns) wrong_count(static_cast<std::size_t>(out - row));
  if (parts_ & kRecoverEnergy)
    max_energy_change_ = std::max(max_energy_change_, std::abs(state_.energy.total() - first_energy_.total()));
}

}  // namespace treedyn
