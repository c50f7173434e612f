#include "designs/subset_simulation/subset_plan.hpp"

#include <span>
#include <string>
#include <vector>

#include "designs/subset_simulation/subset_replay.hpp"

namespace treedyn::designs {
namespace {

class LevelChains final : public ensemble::ChainWave {
 public:
  LevelChains(const EnsembleSpec& spec, const ensemble::Wave& wave)
      : spec_(spec),
        settings_(subset_settings(spec)),
        start_(unpack_level_start(wave.start, spec.input_dimensions())) {}

  double value(const SampleRecord& record) const override { return subset_response(spec_, record); }

  // The chain moves in standard normal space; its runs take the points
  // Phi(u) in the unit cube.
  void run(std::uint64_t c, const Run& run_one) const override {
    const unsigned D = spec_.input_dimensions();
    std::vector<double> uniforms(D);
    const auto response = [&](std::uint64_t k, std::span<const double> u) {
      for (unsigned i = 0; i < D; ++i) uniforms[i] = to_uniform(u[i]);
      return run_one(k, uniforms);
    };
    run_chain(settings_, start_.level, c, start_.threshold, start_.spread,
              std::span<const double>(start_.seed_u.data() + c * D, D), start_.seed_g[c], response);
  }

 private:
  const EnsembleSpec& spec_;
  SubsetSettings settings_;
  LevelStart start_;
};

}  // namespace

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

std::unique_ptr<const ensemble::ChainWave> SubsetPlan::chains(const ensemble::Wave& wave) const {
  return std::make_unique<const LevelChains>(spec_, wave);
}

}  // namespace treedyn::designs
