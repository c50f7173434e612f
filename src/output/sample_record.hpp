// What the ensemble keeps of one sample: its index, how it ended, its
// sampled inputs and the reductions of its trajectory. Everything that moves
// samples around (the MPI transport, checkpoints, part files, the HDF5
// writer, the analysis) speaks in these records.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "integrate/integrator_stats.hpp"

namespace treedyn {

enum class SampleStatus : std::int32_t {
  ok = 0,
  integration_failed = 1,  // the integrator gave up: reason and time reached recorded
  invalid_model = 2,       // the perturbed inputs gave an invalid model (e.g. negative mass)
  not_run = 3,             // a merge of an incomplete set of parts: no part held this sample
};

struct SampleRecord {
  std::uint64_t index = 0;
  SampleStatus status = SampleStatus::ok;
  std::string reason;  // empty when ok
  double time_reached = 0.0;
  IntegratorStats stats;
  std::vector<double> inputs;       // the sampled input values, SI
  std::vector<double> reductions;   // per spec.per_sample reduction, one per column (NaN when failed)
  std::vector<double> responses;    // per spec.responses (NaN when failed)
  std::vector<double> final_state;  // output/final_state.hpp; NaN when failed
  std::vector<double> trajectory;   // times x columns, only for samples < store_trajectories
};

}  // namespace treedyn
