#include "designs/subset_simulation/subset_answer.hpp"

#include <cmath>

#include "designs/subset_simulation/subset_replay.hpp"

namespace treedyn::designs {

std::unique_ptr<const RareEventAnswer> answer_rare_event(const EnsembleSpec& spec,
                                                         const ensemble::ResponseTable& table) {
  SubsetResult result = replay_subset(spec, table, spec.subset->max_levels).result();
  // The runs beyond the limit are mostly the last level's chain states.
  const double gamma = result.levels.empty() ? 0.0 : result.levels.back().gamma;
  analysis::FailureRegion region = analysis::failure_region(
      spec, table, spec.subset->response, [](std::uint64_t) { return true; }, std::isfinite(gamma) ? gamma : 0.0);
  return std::make_unique<const RareEventAnswer>(std::move(result), std::move(region));
}

std::string RareEventAnswer::stop_reason() const {
  const std::string levels = std::to_string(result.levels.size() - 1);
  if (result.no_threshold)
    return "subset simulation: level " + levels +
           " has no threshold (N (1 - p0) or more of its runs failed, "
           "or its responses pile up at one value); the estimate counts that level's exceedances";
  return result.reached_limit ? "subset simulation: the threshold reached the limit at level " + levels
                              : "subset simulation: max_levels (" + levels +
                                    ") reached before the limit; the "
                                    "estimate counts the last level's exceedances";
}

}  // namespace treedyn::designs
