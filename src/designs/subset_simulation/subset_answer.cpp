#include "designs/subset_simulation/subset_answer.hpp"

#include <cmath>

#include "designs/subset_simulation/subset_replay.hpp"

namespace treedyn::designs {

RareEventAnswer answer_rare_event(const ensemble::EnsembleSpec& spec, const ensemble::ResponseTable& table) {
  RareEventAnswer answer{replay_subset(spec, table, spec.subset->max_levels).result(), {}};
  // The runs beyond the limit are mostly the last level's chain states.
  const double gamma = answer.result.levels.empty() ? 0.0 : answer.result.levels.back().gamma;
  answer.region = ensemble::failure_region(
      spec, table, spec.subset->response, [](std::uint64_t) { return true; }, std::isfinite(gamma) ? gamma : 0.0);
  return answer;
}

}  // namespace treedyn::designs
