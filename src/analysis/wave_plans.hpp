// The wave plan of a job: the design's own where it has one (subset
// simulation's levels: designs/registry_analysis.cpp); else one wave for a
// fixed design, or with [ensemble.stop] waves of `every` samples until a
// target holds on the samples so far.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "ensemble/wave_plan.hpp"

namespace treedyn::analysis {

// Which of spec.stop's targets holds on samples 0 .. prefix-1 of `table`,
// said as a sentence with the value reached ("exceedance_cov of
// peak_tension: 0.098 <= 0.1 at 3200 samples"); nullopt when none holds.
std::optional<std::string> stop_reason(const EnsembleSpec& spec, const ensemble::ResponseTable& table,
                                       std::uint64_t prefix);

// Waves [0, every), [every, 2 every), ... up to `samples`; after each, the
// ensemble ends when stop_reason holds on everything before the wave's end.
class StoppingPlan final : public ensemble::WavePlan {
 public:
  explicit StoppingPlan(const EnsembleSpec& spec) : spec_(spec) {}
  ensemble::Wave first_wave() const override;
  std::optional<ensemble::Wave> next_wave(const ensemble::Wave& done,
                                          const ensemble::ResponseTable* so_far) const override;

 private:
  ensemble::Wave wave_from(std::uint64_t first) const;
  const EnsembleSpec& spec_;
};

std::unique_ptr<ensemble::WavePlan> make_wave_plan(const EnsembleSpec& spec);

}  // namespace treedyn::analysis
