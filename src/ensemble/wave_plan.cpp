#include "ensemble/wave_plan.hpp"

namespace treedyn::ensemble {

std::unique_ptr<WavePlan> make_wave_plan(const EnsembleSpec& spec) {
  return std::make_unique<FixedDesignPlan>(spec.samples);
}

}  // namespace treedyn::ensemble
