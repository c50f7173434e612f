// Records the requested quantities of one trajectory at every output time and
// writes them to HDF5.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "dynamics/recovered.hpp"
#include "integrate/settings.hpp"
#include "job/job.hpp"
#include "output/quantities.hpp"

namespace treedyn {

class TrajectoryRecorder {
 public:
  TrajectoryRecorder(const Model& model, const OutputSpec& output);

  // The OutputObserver of simulate().
  void record(const Model& model, const Data& data);

  const std::vector<double>& times() const { return times_; }
  // Row-major samples x columns for quantity k of output.quantities.
  const std::vector<double>& values(std::size_t k) const { return values_[k]; }
  const std::vector<std::string>& columns(std::size_t k) const { return columns_[k]; }
  const std::optional<Recovered>& first() const { return first_; }
  const std::optional<Recovered>& last() const { return last_; }
  // Largest |E(t) - E(0)| seen, J.
  double max_energy_change() const { return max_energy_change_; }

 private:
  const OutputSpec& output_;
  std::vector<const QuantityInfo*> quantities_;
  std::vector<double> times_;
  std::vector<std::vector<double>> values_;
  std::vector<std::vector<std::string>> columns_;
  std::vector<double> row_;
  std::optional<Recovered> first_, last_;
  double max_energy_change_ = 0.0;
};

}  // namespace treedyn
