// [ensemble.subset] of design = "subset_simulation" (read_subset.hpp).
#include "designs/subset_simulation/read_subset.hpp"

#include <cmath>
#include <string>

#include "job/readers.hpp"

namespace treedyn::designs {

// [ensemble.subset] of design = "subset_simulation": the response whose
// limit is the failure, p0, the levels; `samples` is per level, and the
// run count is the most the levels can make: N + max_levels N (1 - p0).
void read_subset(const TomlView& parent, EnsembleSpec& s, std::uint64_t max_runs) {
  refuse_more_runs_than(parent, s.samples, max_runs);  // before the levels multiply it
  const auto section = parent.subtable("subset");
  if (!section)
    parent.fail("design",
                "subset_simulation needs an [ensemble.subset] table with response = NAME (a response "
                "with a limit)");
  const TomlView& t = *section;
  t.check_keys({"response", "level_probability", "max_levels"});
  if (s.input_dimensions() == 0)
    parent.fail("design", "subset_simulation needs at least one [[ensemble.perturbation]] (the uncertain inputs)");
  SubsetSpec subset;
  const std::size_t index = named_response(t, s);
  const Response& response = s.responses[index];
  const std::string& name = response.name;
  if (!response.has_limit())
    t.fail("response", "response \"" + name +
                           "\" has no limit: give it limit and fail_if (the failure whose "
                           "probability is estimated)");
  subset.response = index;
  subset.level_probability = t.number("level_probability", 0.1);
  const double p0 = subset.level_probability;
  if (!(p0 > 0.0 && p0 <= 0.5)) t.fail("level_probability", "must be in (0, 0.5]; 0.1 is the usual value");
  const double inverse = 1.0 / p0;
  if (std::abs(inverse - std::round(inverse)) > 1e-9 * inverse)
    t.fail("level_probability", "1 / level_probability must be a whole number (0.1, 0.2, 0.25, 0.5, ...)");
  const auto states = static_cast<std::uint64_t>(std::llround(inverse));
  if (s.samples % states != 0)
    parent.fail("samples",
                "subset_simulation: samples (per level) x level_probability must be a whole number "
                "of chains: samples must be a multiple of " +
                    std::to_string(states));
  const auto levels = t.integer("max_levels");
  if (levels && (*levels < 1 || *levels > 100)) t.fail("max_levels", "must be from 1 to 100");
  subset.max_levels = levels ? static_cast<int>(*levels) : 10;
  const std::uint64_t chain_runs = s.samples - s.samples / states;
  s.runs = s.samples + static_cast<std::uint64_t>(subset.max_levels) * chain_runs;
  if (s.runs > max_runs)
    parent.fail("samples", "subset_simulation may make samples + max_levels x samples x (1 - level_probability) = " +
                               std::to_string(s.runs) + " runs; at most " + std::to_string(max_runs));
  s.subset = subset;
}

}  // namespace treedyn::designs
