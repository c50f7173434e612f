#include "designs/morris/read_morris.hpp"

#include <string>

namespace treedyn::designs {

// [ensemble.morris]: r trajectories (instead of `samples`) and p levels.
// The units (inputs, groups, a list input as one) are read_groups'.
void read_morris(const TomlView& parent, EnsembleSpec& s, std::uint64_t max_runs) {
  const auto section = parent.subtable("morris");
  if (parent.has("samples"))
    parent.fail("samples",
                "design = \"morris\" runs r trajectories of (G + 1) runs: give r as [ensemble.morris] "
                "trajectories = r, not samples");
  if (!section)
    parent.fail("design", "morris needs an [ensemble.morris] table with trajectories = r (10 to 50 is usual)");
  const TomlView& t = *section;
  t.check_keys({"trajectories", "steps", "levels"});
  if (s.input_dimensions() == 0)
    parent.fail("design", "morris needs at least one [[ensemble.perturbation]] (the inputs to screen)");
  MorrisSpec m;
  const auto r = t.integer("trajectories");
  if (!r) t.fail("trajectories", "missing: the number of trajectories r (an integer >= 2; 10 to 50 is usual)");
  if (*r < 2) t.fail("trajectories", "must be at least 2 (the effects' spread sigma needs two)");
  m.trajectories = static_cast<std::uint64_t>(*r);
  if (const auto steps = t.string("steps")) {
    if (*steps != "radial" && *steps != "trajectories")
      t.fail("steps", "\"" + *steps +
                          "\" is not allowed; use \"radial\" (each step to an independent point) or "
                          "\"trajectories\" (steps of 1/2 in u on p levels)");
    m.radial = *steps == "radial";
  }
  if (m.radial && t.has("levels"))
    t.fail("levels", "only for steps = \"trajectories\" (radial steps go to an independent Sobol' point, no grid)");
  if (m.radial && 2 * s.input_dimensions() > 1000)
    parent.fail("perturbation",
                "morris' radial steps support at most 500 input dimensions (2D Sobol' dimensions); "
                "this job has " +
                    std::to_string(s.input_dimensions()) + ": use steps = \"trajectories\"");
  if (const auto p = t.integer("levels")) {
    if (*p < 2 || *p > 1024 || *p % 2 != 0)
      t.fail("levels", "must be an even integer from 2 to 1024 (a step moves an input p/2 levels)");
    m.levels = static_cast<unsigned>(*p);
  }
  const std::uint64_t per_trajectory = s.unit_count() + 1u;
  const std::string shape = s.grouped ? "(G + 1)" : "(D + 1)";
  if (m.trajectories > max_runs / per_trajectory)
    t.fail("trajectories", "morris makes trajectories x " + shape + " = " + std::to_string(m.trajectories) + " x " +
                               std::to_string(per_trajectory) + " runs; at most " + std::to_string(max_runs) +
                               ": use at most " + std::to_string(max_runs / per_trajectory) + " trajectories");
  s.samples = m.trajectories;
  s.runs = m.trajectories * per_trajectory;
  s.morris = m;
}

}  // namespace treedyn::designs
