// Subset simulation's waves: its levels, each decided from the levels
// replayed so far (rank 0 decides each next level, a resumed run replays
// the same decisions from its restored records).
#pragma once

#include <memory>
#include <optional>

#include "ensemble/wave_plan.hpp"
#include "job/ensemble_spec.hpp"

namespace treedyn::designs {

// Subset simulation: level 0 (samples 0 .. N-1), then each level's chains,
// decided from the levels replayed so far; over when a level's threshold
// reaches the limit or max_levels is reached.
class SubsetPlan final : public ensemble::WavePlan {
 public:
  explicit SubsetPlan(const EnsembleSpec& spec) : spec_(spec) {}
  ensemble::Wave first_wave() const override;
  std::optional<ensemble::Wave> next_wave(const ensemble::Wave& done,
                                          const ensemble::ResponseTable* so_far) const override;
  // A level's Markov chains, from the seeds and spreads its wave carries.
  std::unique_ptr<const ensemble::ChainWave> chains(const ensemble::Wave& wave) const override;

 private:
  const EnsembleSpec& spec_;
};

}  // namespace treedyn::designs
