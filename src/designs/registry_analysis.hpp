// The designs' parts in treedyn_analysis, one line each in
// registry_analysis.cpp (their rules, in treedyn_job: registry.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "designs/design_answer.hpp"
#include "ensemble/response_table.hpp"
#include "ensemble/wave_plan.hpp"
#include "job/ensemble_spec.hpp"

namespace treedyn::designs {

// spec.design's own answer for response r from `table` (Saltelli's Sobol'
// indices, Morris' effects), or none.
std::shared_ptr<const DesignAnswer> design_answer(const EnsembleSpec& spec, const ensemble::ResponseTable& table,
                                                  std::size_t r);

// spec.design's answer for the whole run from `table` (subset simulation's
// P and its levels), or none.
std::unique_ptr<const RunAnswer> run_answer(const EnsembleSpec& spec, const ensemble::ResponseTable& table);

// Run k's point in the unit cube as the run made it, replayed from the
// records of the runs before it in `table`, for a run that follows from them
// (DesignRules::follows_records: subset simulation's levels after level 0);
// none for a run the seed alone gives. Throws
// std::invalid_argument when `table` ends before run k's place is decided.
std::optional<std::vector<double>> replayed_point(const EnsembleSpec& spec, const ensemble::ResponseTable& table,
                                                  std::uint64_t k);

// spec.design's own wave plan (subset simulation's levels), or none: the
// job then runs one wave, or a stopping rule's (analysis/wave_plans.hpp).
std::unique_ptr<ensemble::WavePlan> design_wave_plan(const EnsembleSpec& spec);

}  // namespace treedyn::designs
