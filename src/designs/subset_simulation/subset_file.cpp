// Subset simulation's answer in the ensemble file: /rare_event/<response>,
// and every run's place in the design in /samples.
#include <limits>
#include <string>
#include <vector>

#include "designs/subset_simulation/subset_answer.hpp"
#include "designs/subset_simulation/subset_replay.hpp"

namespace treedyn::designs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void write_levels(AnswerWriter& g, const SubsetResult& result, double sign, const std::string& units) {
  std::vector<double> thresholds, conditional, gamma, acceptance, runs, failed;
  for (const LevelSummary& level : result.levels) {
    thresholds.push_back(sign * level.threshold);
    conditional.push_back(level.conditional_probability);
    gamma.push_back(level.gamma);
    acceptance.push_back(level.acceptance_rate);
    runs.push_back(static_cast<double>(level.runs));
    failed.push_back(static_cast<double>(level.failed_runs));
  }
  const std::vector<std::size_t> n{result.levels.size()};
  g.array("thresholds", thresholds, n, units, "per level: the response's threshold (the last: the limit itself)", {});
  g.array("conditional_probability", conditional, n, "1",
          "per level: the fraction of its states beyond its threshold (p0 but at the last)", {});
  g.array("gamma", gamma, n, "1",
          "per level: the chains' correlation factor in delta_j^2 = (1 - p) / (N p) (1 + gamma)", {});
  g.array("acceptance_rate", acceptance, n, "1", "per level: accepted proposals / proposals (level 0: 1)", {});
  g.array("runs_per_level", runs, n, "1", "per level: the runs it made", {});
  g.array("failed_per_level", failed, n, "1",
          "per level: its runs that failed (never beyond a threshold; rejected proposals)", {});
}

void write_estimate(AnswerWriter& g, const SubsetResult& result) {
  g.value("probability", result.probability, "1",
          "P(limit exceeded) = product of the levels' conditional probabilities");
  g.value("cov", result.cov, "1",
          "coefficient of variation: sqrt(sum of the levels' delta_j^2), the levels taken as "
          "uncorrelated (the usual estimate; it understates a little)");
  g.pair("interval", result.interval_low, result.interval_high,
         "95 % interval: the estimate taken as lognormal with that cov, P exp(-+1.96 sqrt(ln(1 + cov^2))); "
         "with no exceedance at the last level, [0, the rule of three there]");
  g.count("runs", result.runs, "model runs made: every proposal is a run, accepted or not");
  g.value("crude_monte_carlo_runs",
          result.probability > 0.0 && result.cov > 0.0
              ? (1.0 - result.probability) / (result.probability * result.cov * result.cov)
              : kNaN,
          "1", "runs crude Monte Carlo would need for the same cov: (1 - P) / (P cov^2)");
}

// /samples/level, chain and state of runs 0 .. rows-1.
void write_run_places(AnswerWriter& samples, const SubsetSettings& settings, std::size_t rows) {
  std::vector<std::int32_t> levels(rows);
  std::vector<std::int64_t> chains(rows), states(rows);
  for (std::size_t k = 0; k < rows; ++k) {
    const RunPlace p = run_place(settings, k);
    levels[k] = p.level;
    chains[k] = static_cast<std::int64_t>(p.chain);
    states[k] = static_cast<std::int64_t>(p.state);
  }
  samples.column("level", levels, "subset-simulation level of the run (0: the Monte-Carlo level)");
  samples.column("chain", chains, "the run's Markov chain in its level (level 0: the sample)");
  samples.column("state", states,
                 "the run's state in its chain, 1 .. 1/p0 - 1 (state 0, the seed, is a run of the level "
                 "before; level 0: 0)");
}

}  // namespace

void RareEventAnswer::write(AnswerWriter& root, AnswerWriter& samples, const EnsembleSpec& spec,
                            std::size_t rows) const {
  const SubsetSettings settings = subset_settings(spec);
  write_run_places(samples, settings, rows);
  const Response& response = spec.responses[spec.subset->response];
  const double sign = response.fail_if == Response::FailIf::below ? -1.0 : 1.0;
  const std::unique_ptr<AnswerWriter> group =
      root.group("rare_event",
                 "subset simulation (Au and Beck 2001) in standard normal space: levels of "
                 "conditional samples, conditional sampling after Papaioannou et al. 2015");
  const std::unique_ptr<AnswerWriter> g = group->group(response.name.c_str(), "");
  g->attribute("limit", response.limit);
  g->attribute("fail_if", std::string(name(response.fail_if)));
  g->attribute("units", response.units);
  g->attribute("level_probability", settings.level_probability);
  g->attribute("samples_per_level", static_cast<long long>(settings.samples));
  g->attribute("reached_limit", static_cast<long long>(result.reached_limit ? 1 : 0));
  g->attribute("no_threshold", static_cast<long long>(result.no_threshold ? 1 : 0));
  write_estimate(*g, result);
  write_levels(*g, result, sign, response.units);
  g->failure_region(spec, region, "every run beyond the limit (any level)");
}

}  // namespace treedyn::designs
