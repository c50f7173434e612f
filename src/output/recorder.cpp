#include "output/recorder.hpp"

#include <algorithm>
#include <cmath>

namespace treedyn {

Recorder::Recorder(const Model& model, const OutputSpec& output)
    : output_(output), layout_(column_layout(model, output)) {}

void Recorder::clear() {
  times_.clear();
  values_.clear();
  max_energy_change_ = 0.0;
}

void Recorder::record(const Model& model, const Data& data) {
  recover(model, data, state_);
  if (times_.empty()) first_energy_ = state_.energy;
  times_.push_back(state_.time);
  for (const QuantityInfo* q : layout_.info) q->extract(state_, output_, values_);
  max_energy_change_ =
      std::max(max_energy_change_, std::abs(state_.energy.total() - first_energy_.total()));
}

}  // namespace treedyn
