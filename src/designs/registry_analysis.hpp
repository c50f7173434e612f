// The designs' parts in treedyn_analysis, one line each in
// registry_analysis.cpp (their rules, in treedyn_job: registry.cpp).
#pragma once

#include <cstddef>
#include <memory>

#include "designs/design_answer.hpp"
#include "ensemble/response_table.hpp"
#include "ensemble/wave_plan.hpp"
#include "job/ensemble_spec.hpp"

namespace treedyn::designs {

// spec.design's own answer for response r from `table` (Saltelli's Sobol'
// indices, Morris' effects), or none.
std::shared_ptr<const DesignAnswer> design_answer(const ensemble::EnsembleSpec& spec,
                                                  const ensemble::ResponseTable& table, std::size_t r);

// spec.design's own wave plan (subset simulation's levels), or none: the
// job then runs one wave, or a stopping rule's (analysis/wave_plans.hpp).
std::unique_ptr<ensemble::WavePlan> design_wave_plan(const ensemble::EnsembleSpec& spec);

}  // namespace treedyn::designs
