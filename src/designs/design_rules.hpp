// What the rest of the ensemble asks of a sampling design, answered by the
// design itself: one class per design, in its folder (src/designs/<name>/),
// listed once in registry.cpp. The job reader, the answers, the files and
// the summaries ask these rules instead of switching on the design, so that
// a design's words and counting rules live in one place.
//
// A design's own answer for each response (Saltelli's Sobol' indices,
// Morris' effects), its summary lines and its datasets are its
// DesignAnswer, its answer for the whole run (subset simulation's P) its
// RunAnswer (both design_answer.hpp), and a design that plans its waves from
// the answers so far (subset simulation's levels) has its WavePlan: all
// listed in registry_analysis.cpp, with the replay of runs that follow from
// earlier records.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "sampling/design.hpp"

namespace treedyn {
class TomlView;
struct EnsembleSpec;
}  // namespace treedyn
namespace treedyn::sampling {
struct PointsSpec;
class RunPoints;
}  // namespace treedyn::sampling

namespace treedyn::designs {

// A root attribute of the ensemble file that describes the design's runs.
using DesignAttribute = std::pair<std::string, std::variant<long long, std::string>>;

class DesignRules {
 public:
  virtual ~DesignRules() = default;
  virtual sampling::Design design() const = 0;

  // --- its part of the job file ---
  // Its own table, [ensemble.<table>]; empty: none. Any other design's job
  // with that table is refused.
  virtual std::string_view table() const { return {}; }
  // Whether [ensemble] samples is its size (morris: trajectories, in its table).
  virtual bool takes_samples() const { return true; }
  // Reads its table and sets the runs it makes (s.runs; s.samples by
  // default), once the inputs, their units and the responses are read. The
  // job reader refuses more than `max_runs` runs afterwards; a design that
  // multiplies s.samples must refuse first what would overflow. Throws
  // JobError.
  virtual void read_runs(const TomlView& ensemble, EnsembleSpec& s, std::uint64_t max_runs) const;
  // The runs of its first wave, which holds the pilot (wave_plan.hpp).
  virtual std::uint64_t first_wave_runs(const EnsembleSpec& s) const;

  // --- its runs ---
  // Its runs' inputs in the unit cube (sampling/run_points.hpp); may throw
  // std::invalid_argument for a size its generator cannot make.
  virtual std::unique_ptr<sampling::RunPoints> points(const sampling::PointsSpec& spec) const = 0;
  // Runs per step of the design (Saltelli's block, a Morris trajectory): a
  // stopping rule checks, and convergence is told, in whole steps.
  virtual std::uint64_t runs_per_step(const EnsembleSpec&) const { return 1; }
  // Whether run k is an independent draw of the inputs, and so counts for
  // the mean, the standard error, the exceedance and the rank measures.
  virtual bool independent_draw(const EnsembleSpec&, std::uint64_t) const { return true; }
  // Whether run k's inputs follow from the records of the runs before it
  // (subset simulation's levels after level 0), not from the seed alone:
  // rerunning it alone needs the ensemble file, whose records replay it
  // (registry_analysis.hpp: replayed_point). Such a design's `runs` is the
  // most it makes.
  virtual bool follows_records(const EnsembleSpec&, std::uint64_t) const { return false; }
  // Whether any of its runs does: its runs are decided wave by wave, so its
  // ensemble runs as one job, not in parts, and its records arrive as its
  // waves make them, not in units.
  bool adaptive(const EnsembleSpec& s) const;
  // The first runs the responses' answers count, of the `runs` made
  // (subset simulation: level 0, its Monte-Carlo sample).
  virtual std::uint64_t answered_runs(const EnsembleSpec&, std::uint64_t runs) const { return runs; }
  // Whether its RunAnswer answers P(limit exceeded) of response r, in place
  // of the counted runs' exceedance and failure region (subset simulation's
  // response: level 0 alone rarely reaches the limit).
  virtual bool answers_probability(const EnsembleSpec&, std::size_t) const { return false; }
  // Whether the first runs its answers count, in index order, are a design
  // of their own (a response's convergence table is then one; not a Latin
  // hypercube's).
  virtual bool nested_prefixes() const { return true; }
  // Why a stopping rule cannot stop this design early (its first n runs are
  // not a design of their own); empty when one can.
  virtual std::string_view why_no_stopping_rule() const { return {}; }
  // Whether [[ensemble.group]] means anything to it (which inputs move
  // together), and whether a list input is then one factor without groups.
  virtual bool takes_groups() const { return false; }
  virtual bool list_input_is_one_factor() const { return false; }
  // Why it cannot take correlated inputs; empty when it can.
  virtual std::string_view why_no_correlations() const { return {}; }

  // --- its words ---
  // After "there are N samples, 0 .. N-1": how the runs are counted.
  virtual std::string_view runs_note() const { return {}; }
  // Which runs the answers count, where not all ("saltelli: the A and B
  // runs"): after "successful samples with finite values; " in the summary,
  // in parentheses in /responses' description.
  virtual std::string_view counted_runs_note() const { return {}; }
  // /samples' description, /stats' note and /sensitivity/<r>'s description.
  virtual std::string_view samples_description() const { return "one row per sample, by sample index 0 .. samples-1"; }
  virtual std::string_view statistics_note() const { return {}; }
  virtual std::string_view sensitivity_description() const { return "rank measures over the successful samples"; }
  // The root attributes that describe its runs.
  virtual std::vector<DesignAttribute> attributes(const EnsembleSpec&) const { return {}; }
  // The summary's lines on how it makes its runs (--check, the run's start).
  virtual void print_runs(std::ostream&, const EnsembleSpec&) const {}
};

// The rules of `design` (registry.cpp).
const DesignRules& rules_of(sampling::Design design);

}  // namespace treedyn::designs
