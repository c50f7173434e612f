// Subset simulation over an ensemble's records: the settings a job's
// [ensemble.subset] gives, and the levels replayed from the responses of
// the runs so far (rank 0 decides each next level with it, and a resumed run
// replays the same decisions from its restored records).
#pragma once

#include <cstdint>
#include <vector>

#include "designs/subset_simulation/subset_simulation.hpp"
#include "ensemble/response_table.hpp"
#include "job/ensemble_spec.hpp"

namespace treedyn::designs {

// N = samples per level, p0, max_levels, the seed, and the limit as a
// failure g > b: for fail_if = "below", g = -value and b = -limit.
SubsetSettings subset_settings(const EnsembleSpec& spec);

// g of run k: the response with that sign; NaN for a failed run.
double subset_response(const EnsembleSpec& spec, const ensemble::ResponseTable& table, std::uint64_t k);

// ... of one record.
double subset_response(const EnsembleSpec& spec, const SampleRecord& record);

// The uniform numbers of run k of a level after 0, as the run made them: the
// levels before it replayed from `table`, then its chain up to it. Throws
// std::invalid_argument when the table's levels ended before run k.
std::vector<double> subset_uniforms(const EnsembleSpec& spec, const ensemble::ResponseTable& table, std::uint64_t k);

// Levels 0 .. `levels` replayed from `table` (or fewer when the last one is
// reached first), each closed.
SubsetLevels replay_subset(const EnsembleSpec& spec, const ensemble::ResponseTable& table, int levels);

}  // namespace treedyn::designs
