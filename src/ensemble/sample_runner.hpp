// Integrates one ensemble sample (or the nominal run) and reduces its
// trajectory to what the ensemble keeps.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "ensemble/ensemble_spec.hpp"
#include "integrate/settings.hpp"
#include "dynamics/recovered.hpp"
#include "job/job.hpp"
#include "output/quantities.hpp"

namespace treedyn::ensemble {

enum class SampleStatus : std::int32_t {
  ok = 0,
  integration_failed = 1,  // the integrator gave up: reason and time reached recorded
  invalid_model = 2,       // the perturbed inputs gave an invalid model (e.g. negative mass)
};

struct SampleRecord {
  std::uint64_t index = 0;
  SampleStatus status = SampleStatus::ok;
  std::string reason;                // empty when ok
  double time_reached = 0.0;
  IntegratorStats stats;
  std::vector<double> inputs;        // the sampled input values, SI
  std::vector<double> max_over_time; // per column of the recorded quantities (NaN when failed)
  std::vector<double> final_state;   // per body: quaternion q0..q3, angular velocity (inertial);
                                     // NaN when failed
};

// The flat column layout of the recorded quantities (job.output.quantities).
struct ColumnLayout {
  std::vector<std::string> quantity;           // names, in order
  std::vector<const QuantityInfo*> info;       // their catalogue entries
  std::vector<std::size_t> offset;             // first column of each quantity
  std::vector<std::vector<std::string>> names; // column labels of each quantity
  std::size_t columns = 0;
};
ColumnLayout column_layout(const Job& job);

class SampleRunner {
 public:
  SampleRunner(const Job& job, const EnsembleSpec& spec);

  const ColumnLayout& layout() const { return layout_; }
  std::size_t times() const { return job_.request.output_times.size(); }
  std::size_t final_state_size() const { return 7 * static_cast<std::size_t>(job_.model.n); }

  // Sample k, perturbed as the spec says; `nominal` skips the perturbations.
  // On success `trajectory` holds times x columns values (row-major).
  // `between_outputs`, if given, is called at every output time (the MPI
  // driver keeps communication going with it).
  SampleRecord run(std::uint64_t k, bool nominal, std::vector<double>& trajectory,
                   const std::function<void()>& between_outputs = {});

  // The record of a sample that produced nothing: NaN maxima and final state.
  SampleRecord failed_record(std::uint64_t k, SampleStatus status, std::string reason) const;

 private:
  const Job& job_;
  const EnsembleSpec& spec_;
  SampleDesign design_;
  ColumnLayout layout_;
  std::vector<double> uniforms_, row_;
  Recovered state_;  // reused at every output time
};

}  // namespace treedyn::ensemble
