#include "output/recorder.hpp"

#include <algorithm>
#include <cmath>

namespace treedyn {

Recorder::Recorder(const Model& model, const OutputSpec& output, EnergyTracking energy)
    : output_(output),
      layout_(column_layout(model, output)),
      parts_(layout_.needs | (energy == EnergyTracking::on ? kRecoverEnergy : 0u)) {}

void Recorder::clear() {
  times_.clear();
  values_.clear();
  max_energy_change_ = 0.0;
}

void Recorder::record(const Model& model, const Data& data) {
  recover(model, data, state_, parts_);
  if (times_.empty()) first_energy_ = state_.energy;
  times_.push_back(state_.time);
  const std::size_t row = values_.size();
  values_.resize(row + layout_.columns);
  for (std::size_t q = 0; q < layout_.info.size(); ++q)
    layout_.info[q]->extract(state_, output_, values_.data() + row + layout_.offset[q]);
  if (parts_ & kRecoverEnergy)
    max_energy_change_ = std::max(max_energy_change_, std::abs(state_.energy.total() - first_energy_.total()));
}

}  // namespace treedyn
