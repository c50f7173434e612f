#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "analysis/answers.hpp"
#include "analysis/ranking_text.hpp"
#include "designs/design_rules.hpp"

namespace treedyn::ensemble {
namespace {

constexpr std::size_t kFailureShown = 3;  // inputs on a "what makes it exceed" line

// Inputs that are entries of a list target (a sea state's phases).
std::vector<bool> list_entries(const EnsembleSpec& spec) {
  std::vector<bool> hidden;
  for (const Perturbation& p : spec.perturbations)
    for (int k = 0; k < p.dimensions(); ++k) hidden.push_back(p.kind == Perturbation::Kind::parameter_list);
  return hidden;
}

// The design's own ranking (Saltelli's Sobol' indices, Morris' mu*), or
// else the ranking by |SRRC| or |Spearman|.
void print_drivers(std::ostream& out, const EnsembleSpec& spec, const Response& response, const ResponseAnswer& a) {
  if (a.design) return a.design->print(out, spec, response);
  const RankSensitivity& r = a.ranks;
  if (r.spearman.empty()) return;
  std::vector<double> measure(r.spearman.size());
  for (std::size_t i = 0; i < measure.size(); ++i) measure[i] = std::abs(r.ranked_by_srrc ? r.srrc[i] : r.spearman[i]);
  out << "    drivers (" << (r.ranked_by_srrc ? "|SRRC|" : "|Spearman|") << ", over " << r.samples << " runs): ";
  print_ranking(out, spec.input_names(), r.ranking, measure, nullptr, "runs", list_entries(spec));
}

// One unit of the failure region: its importance and, for a single input,
// where the failing runs put it (mean u, the design point).
std::string failure_unit_text(const EnsembleSpec& spec, const FailureRegion& region, std::size_t u) {
  std::string t = region.units[u].name + " " + number(region.unit_importance[u], "%.2f");
  if (region.units[u].inputs.size() != 1) return t + " (" + std::to_string(region.units[u].inputs.size()) + " inputs)";
  const unsigned i = region.units[u].inputs.front();
  return t + " (mean u " + number(region.mean_u[i], "%.2f") + ", design point " +
         number(region.design_point[i], "%.4g") + " " + spec.input_units()[i] + ")";
}

// The inputs the failing runs select on, by importance, and a warning for
// every input whose truncation bound holds most of them.
void print_failure_region(std::ostream& out, const EnsembleSpec& spec, const FailureRegion& region, const char* what) {
  if (region.runs == 0 || region.unit_importance.empty()) return;
  const std::size_t inputs = region.mean_u.size();
  out << "    what makes it exceed (" << region.runs << " " << what << "; importance):";
  if (std::none_of(region.unit_importance.begin(), region.unit_importance.end(),
                   [](double v) { return std::isfinite(v); }))
    out << " no input departs from its own distribution beyond chance";
  const Ranking order = rank_units(region.unit_importance, {}, region.runs);
  for (std::size_t k = 0; k < std::min(order.order.size(), kFailureShown); ++k) {
    if (!(region.unit_importance[order.order[k]] > 0.0)) break;
    out << (k ? "; " : " ") << failure_unit_text(spec, region, order.order[k]);
  }
  out << "\n";
  const double enough = static_cast<double>(std::max<std::uint64_t>(kFailureRegionRuns, inputs));
  if (region.effective_runs < enough)
    out << "      rough: " << region.runs << " runs beyond the limit"
        << (region.effective_runs < static_cast<double>(region.runs)
                ? " (as " + number(region.effective_runs, "%.0f") + " independent ones: chain states)"
                : std::string())
        << " for " << inputs << " inputs (chance alone moves each input's share; at least " << number(enough, "%.0f")
        << " would tell)\n";
  const std::vector<std::string> names = spec.input_names(), units = spec.input_units();
  for (std::size_t i = 0; i < inputs; ++i)
    if (region.near_bound[i] >= kBoundSetsProbability)
      out << "      warning: " << number(100.0 * region.near_bound[i], "%.0f") << " % of them have " << names[i]
          << " within " << number(100.0 * kNearBoundShare, "%.0f") << " % of its range of its bound "
          << number(region.bound[i], "%.6g") << " " << units[i]
          << ": P depends on where that distribution is cut off, not only on the dynamics\n";
}

}  // namespace

void print_response_summary(std::ostream& out, const EnsembleSpec& spec, const std::vector<ResponseAnswer>& answers,
                            const ToleranceCheck& tolerance) {
  if (answers.empty()) return;
  out << "responses: mean +- standard error (successful samples with finite values"
      << designs::rules_of(spec.design).counted_runs_note() << ")\n";
  for (std::size_t r = 0; r < answers.size(); ++r) {
    const Response& response = spec.responses[r];
    const ResponseAnswer& a = answers[r];
    std::string what = std::string(name(response.reduce)) + " of " + response.quantity + " " + response.column;
    if (response.reduce == Response::Reduce::at_time) what += " at t = " + number(response.time) + " s";
    if (response.reduce == Response::Reduce::first_time_above || response.reduce == Response::Reduce::first_time_below)
      what += " " + number(response.threshold);
    out << "  " << response.name << " (" << what << "): " << number(a.mean) << " +- " << number(a.sem, "%.3g") << " "
        << response.units << "  [" << a.used << " used";
    if (a.not_finite > 0) out << ", " << a.not_finite << " never crossed (+inf)";
    if (a.failed > 0) out << ", " << a.failed << " failed";
    out << "]\n";
    if (r < tolerance.change.size()) out << "    integration: " << describe_verdict(tolerance, r) << "\n";
    const bool subset_answer = spec.subset && spec.subset->response == r;
    if (subset_answer && a.exceedance) {
      out << "    P: subset simulation's answer, below (level 0, its Monte-Carlo sample, has " << a.exceedance->exceeded
          << " of " << a.exceedance->successful << " beyond the limit)\n";
      print_drivers(out, spec, response, a);
      continue;
    }
    if (const auto& e = a.exceedance) {
      out << "    P(" << response.name << (response.fail_if == Response::FailIf::above ? " > " : " < ")
          << number(response.limit) << " " << response.units << ") = " << number(e->probability, "%.4g") << " ("
          << e->exceeded << " of " << e->successful << "), 95 % Wilson interval [" << number(e->interval.low, "%.4g")
          << ", " << number(e->interval.high, "%.4g") << "]";
      out << "\n";
      if (e->failed > 0)
        out << "      " << e->failed << " failed samples are not in the count: counted as not exceeding or as "
            << "exceeding, P would be " << number(e->with_failed.low, "%.4g") << " to "
            << number(e->with_failed.high, "%.4g") << "\n";
    }
    print_drivers(out, spec, response, a);
    if (a.failure_region) print_failure_region(out, spec, *a.failure_region, "counted runs beyond the limit");
  }
}

void print_rare_event(std::ostream& out, const EnsembleSpec& spec, const RareEventAnswer& answer) {
  const rare_event::SubsetResult& result = answer.result;
  const Response& response = spec.responses[spec.subset->response];
  const double sign = response.fail_if == Response::FailIf::below ? -1.0 : 1.0;
  const char* side = response.fail_if == Response::FailIf::above ? " > " : " < ";
  out << "subset simulation: P(" << response.name << side << number(response.limit) << " " << response.units
      << ") = " << number(result.probability, "%.4g") << ", cov " << number(result.cov, "%.3g")
      << " (levels taken as uncorrelated), 95 % interval [" << number(result.interval_low, "%.4g") << ", "
      << number(result.interval_high, "%.4g") << "]"
      << (result.probability > 0.0 ? " (lognormal)\n"
                                   : " (none beyond the limit: the rule of three at the last level)\n");
  out << "  " << result.runs << " runs in " << result.levels.size() << " levels of " << spec.samples << "; thresholds:";
  for (const rare_event::LevelSummary& level : result.levels) out << " " << number(sign * level.threshold, "%.5g");
  out << " " << response.units << "\n";
  if (result.probability > 0.0 && result.cov > 0.0)
    out << "  crude Monte Carlo would need about "
        << number((1.0 - result.probability) / (result.probability * result.cov * result.cov), "%.3g")
        << " runs for the same cov\n";
  if (result.no_threshold)
    out << "  warning: the last level has no threshold (N (1 - p0) or more of its runs failed, or its responses "
           "pile up at one value): the estimate counts that level's exceedances and may be far off; see "
           "/samples/status and /samples/reason\n";
  else if (!result.reached_limit)
    out << "  warning: max_levels ran out before a level's threshold reached the limit: the estimate counts "
           "the last level's exceedances (raise max_levels)\n";
  print_failure_region(out, spec, answer.region, "runs beyond the limit, any level");
}

}  // namespace treedyn::ensemble
