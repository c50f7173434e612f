#include "designs/subset_simulation/subset_replay.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace treedyn::designs {

SubsetSettings subset_settings(const EnsembleSpec& spec) {
  const Response& r = spec.responses[spec.subset->response];
  SubsetSettings s;
  s.samples = spec.samples;
  s.level_probability = spec.subset->level_probability;
  s.max_levels = spec.subset->max_levels;
  s.seed = spec.seed;
  s.limit = r.fail_if == Response::FailIf::below ? -r.limit : r.limit;
  return s;
}

double subset_response(const EnsembleSpec& spec, const ensemble::ResponseTable& table, std::uint64_t k) {
  // A run the table does not hold (a file cut short, or another build's
  // levels) reads as failed rather than past the end.
  if (k >= table.samples() || !table.ok(k)) return std::numeric_limits<double>::quiet_NaN();
  const std::size_t r = spec.subset->response;
  const double value = table.response(k, r);
  return spec.responses[r].fail_if == Response::FailIf::below ? -value : value;
}

double subset_response(const EnsembleSpec& spec, const SampleRecord& record) {
  if (record.status != SampleStatus::ok) return std::numeric_limits<double>::quiet_NaN();
  const std::size_t r = spec.subset->response;
  return spec.responses[r].fail_if == Response::FailIf::below ? -record.responses[r] : record.responses[r];
}

SubsetLevels replay_subset(const EnsembleSpec& spec, const ensemble::ResponseTable& table, int levels) {
  SubsetLevels replay(subset_settings(spec), spec.input_dimensions());
  const auto recorded = [&](std::uint64_t k, std::span<const double>) { return subset_response(spec, table, k); };
  replay.start(recorded);
  while (replay.level() < levels && !replay.finished()) replay.advance(recorded);
  return replay;
}

std::vector<double> subset_uniforms(const EnsembleSpec& spec, const ensemble::ResponseTable& table, std::uint64_t k) {
  const SubsetSettings settings = subset_settings(spec);
  const RunPlace place = run_place(settings, k);
  const unsigned D = spec.input_dimensions();
  if (place.level == 0) throw std::invalid_argument("run " + std::to_string(k) + " is in level 0: the design's own");
  const SubsetLevels levels = replay_subset(spec, table, place.level - 1);
  if (levels.level() != place.level - 1 || levels.finished() || k >= table.samples())
    throw std::invalid_argument("run " + std::to_string(k) + " (level " + std::to_string(place.level) +
                                ") was not made: the file's levels end before it");
  const LevelStart start = levels.next_start();
  std::vector<double> u(D);
  const auto recorded = [&](std::uint64_t index, std::span<const double> v) {
    if (index == k) std::copy(v.begin(), v.end(), u.begin());
    return index < table.samples() ? subset_response(spec, table, index) : std::numeric_limits<double>::quiet_NaN();
  };
  run_chain(settings, start.level, place.chain, start.threshold, start.spread,
            std::span<const double>(start.seed_u.data() + place.chain * D, D), start.seed_g[place.chain], recorded);
  for (double& v : u) v = to_uniform(v);
  return u;
}

}  // namespace treedyn::designs
