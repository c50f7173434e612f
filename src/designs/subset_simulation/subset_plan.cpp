#include "designs/subset_simulation/subset_plan.hpp"

#include <string>

#include "designs/subset_simulation/subset_replay.hpp"

namespace treedyn::designs {

ensemble::Wave SubsetPlan::first_wave() const { return {0, spec_.samples, "level 0", 0, {}}; }

std::optional<ensemble::Wave> SubsetPlan::next_wave(const ensemble::Wave& done,
                                                    const ensemble::ResponseTable* so_far) const {
  if (!so_far) return std::nullopt;
  const SubsetSettings settings = subset_settings(spec_);
  const int level = run_place(settings, done.first).level;
  const SubsetLevels levels = replay_subset(spec_, *so_far, level);
  if (levels.finished()) return std::nullopt;
  const int next = level + 1;
  return ensemble::Wave{runs_before(settings, next), runs_before(settings, next + 1), "level " + std::to_string(next),
                        settings.states() - 1, pack(levels.next_start())};
}

}  // namespace treedyn::designs
