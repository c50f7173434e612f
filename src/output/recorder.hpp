// Records the requested quantities of one trajectory at every output time,
// as one flat row of columns per time. `treedyn run` and every ensemble
// sample use this one recorder.
#pragma once

#include <vector>

#include "dynamics/data.hpp"
#include "dynamics/recovered.hpp"
#include "model/model.hpp"
#include "output/output_spec.hpp"
#include "output/quantities.hpp"

namespace treedyn {

// Whether a recorder follows the energy (for `treedyn run`'s summary) even
// when no recorded quantity needs it.
enum class EnergyTracking { off, on };

class Recorder {
 public:
  // `model` names the columns (any model of the same tree); `output` must
  // outlive the recorder. It recovers only what its quantities read (and
  // the energy when tracking it).
  Recorder(const Model& model, const OutputSpec& output, EnergyTracking energy = EnergyTracking::off);
  // Whether the observed state must carry accelerations: the request's
  // accelerations_at_outputs (integrate/simulate.hpp).
  bool needs_accelerations() const { return (parts_ & kRecoverAccelerations) != 0; }

  // Forgets the recorded trajectory (keeping its storage) before a new one.
  void clear();
  // The OutputObserver of simulate(): recovers the state and appends a row.
  // Throws std::invalid_argument for a model of another number of bodies.
  void record(const Model& model, const Data& data);

  const ColumnLayout& layout() const { return layout_; }
  const std::vector<double>& times() const { return times_; }
  // times x columns, row-major.
  const std::vector<double>& values() const { return values_; }
  // Exchanges the recorded values with `other` (no copy; the recorder keeps
  // `other`'s storage for the next trajectory).
  void swap_values(std::vector<double>& other) { values_.swap(other); }
  bool empty() const { return times_.empty(); }
  // The state at the last output time recorded.
  const Recovered& last() const { return state_; }
  // With EnergyTracking::on: energies at the first output time, and the
  // largest |E(t) - E(first)| seen, J (zero otherwise).
  const Energies& first_energy() const { return first_energy_; }
  double max_energy_change() const { return max_energy_change_; }

 private:
  const OutputSpec& output_;
  // Out of line and cold: record() runs at every output time.
  [[noreturn, gnu::cold, gnu::noinline]] void wrong_count(std::size_t written) const;
  [[noreturn, gnu::cold, gnu::noinline]] void wrong_model(const Model& model) const;

  ColumnLayout layout_;
  int bodies_;      // of the model the columns were named for
  unsigned parts_;  // RecoveredPart flags recover() computes
  std::vector<double> times_, values_;
  Recovered state_;  // reused at every output time
  Energies first_energy_;
  double max_energy_change_ = 0.0;
};

}  // namespace treedyn
