#include "designs/subset_simulation/subset_file.hpp"

#include <limits>
#include <string>
#include <vector>

#include "hdf5/answer_datasets.hpp"
#include "hdf5/described.hpp"

namespace treedyn::designs {
namespace {

using answers_file::fail_if_name;  // the datasets every design's answers are written with
using answers_file::write_failure_region;
using answers_file::write_pair;
using h5::describe;
using h5::write_described_scalar;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void write_levels(hid_t g, const designs::SubsetResult& result, double sign, const std::string& units) {
  std::vector<double> thresholds, conditional, gamma, acceptance, runs, failed;
  for (const designs::LevelSummary& level : result.levels) {
    thresholds.push_back(sign * level.threshold);
    conditional.push_back(level.conditional_probability);
    gamma.push_back(level.gamma);
    acceptance.push_back(level.acceptance_rate);
    runs.push_back(static_cast<double>(level.runs));
    failed.push_back(static_cast<double>(level.failed_runs));
  }
  describe(h5::write_vector(g, "thresholds", thresholds).id(), units,
           "per level: the response's threshold (the last: the limit itself)", {});
  describe(h5::write_vector(g, "conditional_probability", conditional).id(), "1",
           "per level: the fraction of its states beyond its threshold (p0 but at the last)", {});
  describe(h5::write_vector(g, "gamma", gamma).id(), "1",
           "per level: the chains' correlation factor in delta_j^2 = (1 - p) / (N p) (1 + gamma)", {});
  describe(h5::write_vector(g, "acceptance_rate", acceptance).id(), "1",
           "per level: accepted proposals / proposals (level 0: 1)", {});
  describe(h5::write_vector(g, "runs_per_level", runs).id(), "1", "per level: the runs it made", {});
  describe(h5::write_vector(g, "failed_per_level", failed).id(), "1",
           "per level: its runs that failed (never beyond a threshold; rejected proposals)", {});
}

}  // namespace

void write_rare_event(hid_t file, const ensemble::EnsembleSpec& spec, const designs::SubsetSettings& settings,
                      const RareEventAnswer& answer) {
  const designs::SubsetResult& result = answer.result;
  const ensemble::Response& response = spec.responses[spec.subset->response];
  const double sign = response.fail_if == ensemble::Response::FailIf::below ? -1.0 : 1.0;
  h5::Handle group = h5::create_group(file, "rare_event");
  h5::write_attribute(group.id(), "description",
                      std::string("subset simulation (Au and Beck 2001) in standard normal space: levels of "
                                  "conditional samples, conditional sampling after Papaioannou et al. 2015"));
  h5::Handle g = h5::create_group(group.id(), response.name);
  h5::write_attribute(g.id(), "limit", response.limit);
  h5::write_attribute(g.id(), "fail_if", fail_if_name(response));
  h5::write_attribute(g.id(), "units", response.units);
  h5::write_attribute(g.id(), "level_probability", settings.level_probability);
  h5::write_attribute(g.id(), "samples_per_level", static_cast<long long>(settings.samples));
  h5::write_attribute(g.id(), "reached_limit", static_cast<long long>(result.reached_limit ? 1 : 0));
  h5::write_attribute(g.id(), "no_threshold", static_cast<long long>(result.no_threshold ? 1 : 0));
  write_described_scalar(g.id(), "probability", result.probability, "1",
                         "P(limit exceeded) = product of the levels' conditional probabilities");
  write_described_scalar(g.id(), "cov", result.cov, "1",
                         "coefficient of variation: sqrt(sum of the levels' delta_j^2), the levels taken as "
                         "uncorrelated (the usual estimate; it understates a little)");
  write_pair(g.id(), "interval", result.interval_low, result.interval_high,
             "95 % interval: the estimate taken as lognormal with that cov, P exp(-+1.96 sqrt(ln(1 + cov^2))); "
             "with no exceedance at the last level, [0, the rule of three there]");
  write_described_scalar(g.id(), "runs", result.runs, "1", "model runs made: every proposal is a run, accepted or not");
  write_described_scalar(g.id(), "crude_monte_carlo_runs",
                         result.probability > 0.0 && result.cov > 0.0
                             ? (1.0 - result.probability) / (result.probability * result.cov * result.cov)
                             : kNaN,
                         "1", "runs crude Monte Carlo would need for the same cov: (1 - P) / (P cov^2)");
  write_levels(g.id(), result, sign, response.units);
  write_failure_region(g.id(), spec, answer.region, "every run beyond the limit (any level)");
}

}  // namespace treedyn::designs
