#include "output/recorder.hpp"

#include <algorithm>
#include <cmath>

#include "output/quantities.hpp"

namespace treedyn {

TrajectoryRecorder::TrajectoryRecorder(const Model& model, const OutputSpec& output)
    : output_(output), values_(output.quantities.size()) {
  for (const std::string& q : output.quantities) {
    quantities_.push_back(find_quantity(q));
    columns_.push_back(quantity_columns(q, model, output));
  }
}

void TrajectoryRecorder::record(const Model& model, const Data& data) {
  Recovered state = recover(model, data);
  times_.push_back(state.time);
  for (std::size_t k = 0; k < output_.quantities.size(); ++k) {
    row_.clear();
    quantities_[k]->extract(state, output_, row_);
    values_[k].insert(values_[k].end(), row_.begin(), row_.end());
  }
  if (!first_) first_ = state;
  max_energy_change_ =
      std::max(max_energy_change_, std::abs(state.energy.total() - first_->energy.total()));
  last_ = std::move(state);
}

}  // namespace treedyn
