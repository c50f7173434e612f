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
      parts_(layout_.needs | (energy == EnergyTracking::on ? kRecoverEnergy : 0u)) {
  for (std::size_t q = 0; q < layout_.info.size(); ++q) ends_.push_back(layout_.offset[q] + layout_.names[q].size());
}

void Recorder::clear() {
  times_.clear();
  values_.clear();
  max_energy_change_ = 0.0;
}

void Recorder::wrong_count(std::size_t q) const {
  throw std::logic_error("recorder: quantity " + layout_.quantity[q] + " wrote another number of values than " +
                         std::to_string(layout_.names[q].size()) + " columns");
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
  double* const row = values_.data() + at;
  // A quantity that wrote another count than it names would shift or
  // overrun the row: a programming error, stopped at its first row.
  for (std::size_t q = 0; q < layout_.info.size(); ++q)
    if (layout_.info[q]->extract(state_, output_, row + layout_.offset[q]) != row + ends_[q]) wrong_count(q);
  if (parts_ & kRecoverEnergy)
    max_energy_change_ = std::max(max_energy_change_, std::abs(state_.energy.total() - first_energy_.total()));
}

}  // namespace treedyn
