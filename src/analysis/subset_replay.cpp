#include "analysis/subset_replay.hpp"

#include <limits>

namespace treedyn::ensemble {

rare_event::SubsetSettings subset_settings(const EnsembleSpec& spec) {
  const Response& r = spec.responses[spec.subset->response];
  rare_event::SubsetSettings s;
  s.samples = spec.base_samples;
  s.level_probability = spec.subset->level_probability;
  s.max_levels = spec.subset->max_levels;
  s.seed = spec.seed;
  s.limit = r.fail_if == Response::FailIf::below ? -r.limit : r.limit;
  return s;
}

double subset_response(const EnsembleSpec& spec, const ResponseTable& table, std::uint64_t k) {
  if (!table.ok(k)) return std::numeric_limits<double>::quiet_NaN();
  const std::size_t r = spec.subset->response;
  const double value = table.response(k, r);
  return spec.responses[r].fail_if == Response::FailIf::below ? -value : value;
}

double subset_response(const EnsembleSpec& spec, const SampleRecord& record) {
  if (record.status != SampleStatus::ok) return std::numeric_limits<double>::quiet_NaN();
  const std::size_t r = spec.subset->response;
  return spec.responses[r].fail_if == Response::FailIf::below ? -record.responses[r] : record.responses[r];
}

rare_event::SubsetLevels replay_subset(const EnsembleSpec& spec, const ResponseTable& table, int levels) {
  rare_event::SubsetLevels replay(subset_settings(spec), spec.input_dimensions());
  const auto recorded = [&](std::uint64_t k, std::span<const double>) { return subset_response(spec, table, k); };
  replay.start(recorded);
  while (replay.level() < levels && !replay.finished()) replay.advance(recorded);
  return replay;
}

}  // namespace treedyn::ensemble
