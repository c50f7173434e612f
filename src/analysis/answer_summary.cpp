#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "analysis/answers.hpp"

namespace treedyn::ensemble {
namespace {

std::string number(double v, const char* format = "%.6g") {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
}

// The inputs (a grouped design: the groups) that matter most: by total
// Sobol' index (saltelli), else by |Spearman|; at most three.
void print_drivers(std::ostream& out, const EnsembleSpec& spec, const ResponseAnswer& a) {
  std::vector<std::string> names = spec.input_names();
  const bool sobol = a.sobol.has_value();
  if (sobol && spec.grouped) {
    names.clear();
    for (const SobolUnit& unit : spec.sobol_units) names.push_back(unit.name);
  }
  const std::vector<double>& measure = sobol ? a.sobol->total : a.ranks.spearman;
  if (measure.size() != names.size() || names.empty()) return;
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < names.size(); ++i)
    if (std::isfinite(measure[i])) order.push_back(i);
  if (order.empty()) return;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    return std::abs(measure[x]) > std::abs(measure[y]);
  });
  out << "    drivers (" << (sobol && spec.grouped ? "groups, total Sobol' index"
                          : sobol                ? "total Sobol' index"
                                                 : "Spearman rank correlation")
      << "):";
  for (std::size_t k = 0; k < std::min<std::size_t>(order.size(), 3); ++k)
    out << (k ? "," : "") << " " << names[order[k]] << " " << number(measure[order[k]], "%.3g");
  out << "\n";
}

}  // namespace

void print_response_summary(std::ostream& out, const EnsembleSpec& spec,
                            const std::vector<ResponseAnswer>& answers) {
  if (answers.empty()) return;
  out << "responses: mean +- standard error (successful samples with finite values"
      << (spec.design == Design::saltelli            ? "; saltelli: the A and B runs"
          : spec.design == Design::subset_simulation ? "; subset_simulation: level 0, the Monte-Carlo level"
                                                     : "")
      << ")\n";
  for (std::size_t r = 0; r < answers.size(); ++r) {
    const Response& response = spec.responses[r];
    const ResponseAnswer& a = answers[r];
    std::string what = std::string(name(response.reduce)) + " of " + response.quantity + " " + response.column;
    if (response.reduce == Response::Reduce::at_time) what += " at t = " + number(response.time) + " s";
    if (response.reduce == Response::Reduce::first_time_above || response.reduce == Response::Reduce::first_time_below)
      what += " " + number(response.threshold);
    out << "  " << response.name << " (" << what << "): " << number(a.mean) << " +- "
        << number(a.sem, "%.3g") << " " << response.units << "  [" << a.used << " used";
    if (a.not_finite > 0) out << ", " << a.not_finite << " never crossed (+inf)";
    if (a.failed > 0) out << ", " << a.failed << " failed";
    out << "]\n";
    if (const auto& e = a.exceedance) {
      out << "    P(" << response.name << (response.fail_if == Response::FailIf::above ? " > " : " < ")
          << number(response.limit) << " " << response.units << ") = " << number(e->probability, "%.4g")
          << " (" << e->exceeded << " of " << e->successful << "), 95 % Wilson interval ["
          << number(e->interval.low, "%.4g") << ", " << number(e->interval.high, "%.4g") << "]";
      if (e->failed > 0) out << "; " << e->failed << " failed samples not in the count";
      out << "\n";
    }
    print_drivers(out, spec, a);
  }
}

void print_rare_event(std::ostream& out, const EnsembleSpec& spec, const rare_event::SubsetResult& result) {
  const Response& response = spec.responses[spec.subset->response];
  const double sign = response.fail_if == Response::FailIf::below ? -1.0 : 1.0;
  const char* side = response.fail_if == Response::FailIf::above ? " > " : " < ";
  out << "subset simulation: P(" << response.name << side << number(response.limit) << " " << response.units
      << ") = " << number(result.probability, "%.4g") << ", cov " << number(result.cov, "%.3g")
      << " (levels taken as uncorrelated), 95 % interval [" << number(result.interval_low, "%.4g") << ", "
      << number(result.interval_high, "%.4g") << "]"
      << (result.probability > 0.0 ? " (lognormal)\n" : " (none beyond the limit: the rule of three at the last level)\n");
  out << "  " << result.runs << " runs in " << result.levels.size() << " levels of " << spec.base_samples
      << "; thresholds:";
  for (const rare_event::LevelSummary& level : result.levels) out << " " << number(sign * level.threshold, "%.5g");
  out << " " << response.units << "\n";
  if (result.probability > 0.0 && result.cov > 0.0)
    out << "  crude Monte Carlo would need about "
        << number((1.0 - result.probability) / (result.probability * result.cov * result.cov), "%.3g")
        << " runs for the same cov\n";
  if (result.no_threshold)
    out << "  warning: the last level has no threshold (more than N (1 - p0) of its runs failed, or its responses "
           "pile up at one value): the estimate counts that level's exceedances and may be far off; see "
           "/samples/status and /samples/reason\n";
  else if (!result.reached_limit)
    out << "  warning: max_levels ran out before a level's threshold reached the limit: the estimate counts "
           "the last level's exceedances (raise max_levels)\n";
}

}  // namespace treedyn::ensemble
