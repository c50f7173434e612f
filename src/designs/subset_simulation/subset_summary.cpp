// Subset simulation's lines in the end-of-run summary.
#include "analysis/summary_text.hpp"
#include "designs/subset_simulation/subset_answer.hpp"

namespace treedyn::designs {

void RareEventAnswer::print(std::ostream& out, const EnsembleSpec& spec) const {
  const Response& response = spec.responses[spec.subset->response];
  const double sign = response.fail_if == Response::FailIf::below ? -1.0 : 1.0;
  const char* side = response.fail_if == Response::FailIf::above ? " > " : " < ";
  out << "subset simulation: P(" << response.name << side << analysis::number(response.limit) << " " << response.units
      << ") = " << analysis::number(result.probability, "%.4g") << ", cov " << analysis::number(result.cov, "%.3g")
      << " (levels taken as uncorrelated), 95 % interval [" << analysis::number(result.interval_low, "%.4g") << ", "
      << analysis::number(result.interval_high, "%.4g") << "]"
      << (result.probability > 0.0 ? " (lognormal)\n"
                                   : " (none beyond the limit: the rule of three at the last level)\n");
  out << "  " << result.runs << " runs in " << result.levels.size() << " levels of " << spec.samples << "; thresholds:";
  for (const LevelSummary& level : result.levels) out << " " << analysis::number(sign * level.threshold, "%.5g");
  out << " " << response.units << "\n";
  if (result.probability > 0.0 && result.cov > 0.0)
    out << "  crude Monte Carlo would need about "
        << analysis::number((1.0 - result.probability) / (result.probability * result.cov * result.cov), "%.3g")
        << " runs for the same cov\n";
  if (result.no_threshold)
    out << "  warning: the last level has no threshold (N (1 - p0) or more of its runs failed, or its responses "
           "pile up at one value): the estimate counts that level's exceedances and may be far off; see "
           "/samples/status and /samples/reason\n";
  else if (!result.reached_limit)
    out << "  warning: max_levels ran out before a level's threshold reached the limit: the estimate counts "
           "the last level's exceedances (raise max_levels)\n";
  analysis::print_failure_region(out, spec, region, "runs beyond the limit, any level");
}

}  // namespace treedyn::designs
