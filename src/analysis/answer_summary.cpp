#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "analysis/answers.hpp"
#include "designs/design_rules.hpp"

namespace treedyn::ensemble {
namespace {

std::string number(double v, const char* format = "%.6g") {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
}

constexpr std::size_t kRankedShown = 5;   // units on a drivers line
constexpr std::size_t kFailureShown = 3;  // inputs on a "what makes it exceed" line

std::string clipped(double v) { return number(std::clamp(v, 0.0, 1.0), "%.2g"); }

// "name 0.84 [0.61, 0.97]": an index with its interval, shown within [0, 1]
// (`index`), or a measure with its interval as it is.
std::string index_text(const std::string& name, double v, const double* ci, bool index) {
  std::string t = name + " " + number(v, index ? "%.2g" : "%.3g");
  if (ci && std::isfinite(ci[0]))
    t += " [" + (index ? clipped(ci[0]) : number(ci[0], "%.3g")) + ", " +
         (index ? clipped(ci[1]) : number(ci[1], "%.3g")) + "]";
  return t;
}

// The units in ranked order, ">" where the bootstrap tells neighbours apart
// and "~" where it does not yet, then how many samples would tell the first
// such pair apart.
// The ranked units `hidden` does not hide (a list's entries, one by one:
// noise to a reader), ">" between two shown neighbours where some pair
// between them in the full order is told apart, "~" where none is yet.
void print_ranking(std::ostream& out, const std::vector<std::string>& names, const Ranking& ranking,
                   const std::vector<double>& measure, const std::vector<double>* ci, const char* samples_word,
                   const std::vector<bool>& hidden = {}, bool indices = true) {
  std::vector<std::size_t> places;  // places in ranking.order of the units shown
  for (std::size_t k = 0; k < ranking.order.size(); ++k)
    if (hidden.empty() || !hidden[ranking.order[k]]) places.push_back(k);
  const std::size_t shown = std::min(places.size(), kRankedShown);
  std::string pending;
  for (std::size_t s = 0; s < shown; ++s) {
    const std::size_t u = ranking.order[places[s]];
    if (s > 0) {
      bool apart = false;
      for (std::size_t k = places[s - 1]; k < places[s]; ++k) apart = apart || ranking.told_apart(k);
      out << (apart ? " > " : " ~ ");
      if (!apart && pending.empty() && places[s] == places[s - 1] + 1 && std::isfinite(ranking.needed[places[s - 1]]))
        pending = "about " + number(ranking.needed[places[s - 1]], "%.0f") + " " + samples_word + " would tell " +
                  names[ranking.order[places[s - 1]]] + " from " + names[u];
    }
    out << index_text(names[u], measure[u], ci ? ci->data() + 2 * u : nullptr, indices);
  }
  if (places.size() > shown) out << " (and " << places.size() - shown << " more)";
  if (places.size() < ranking.order.size())
    out << " (not shown: " << ranking.order.size() - places.size() << " entries of lists, one by one)";
  out << "\n";
  if (ranking.resamples == 0)
    out << "      no bootstrap intervals: the order above is the point estimates' alone\n";
  else if (!pending.empty())
    out << "      ~: not told apart yet (95 % bootstrap interval of the difference holds 0); " << pending << "\n";
  if (ci && indices &&
      std::any_of(places.begin(), places.begin() + static_cast<std::ptrdiff_t>(shown), [&](std::size_t k) {
        const double v = measure[ranking.order[k]];
        return v < 0.0 || v > 1.0;
      }))
    out << "      an index estimated outside [0, 1] is noise of a small sample; its interval is shown within [0, 1]\n";
}

// Inputs that are entries of a list target (a sea state's phases).
std::vector<bool> list_entries(const EnsembleSpec& spec) {
  std::vector<bool> hidden;
  for (const Perturbation& p : spec.perturbations)
    for (int k = 0; k < p.dimensions(); ++k) hidden.push_back(p.kind == Perturbation::Kind::parameter_list);
  return hidden;
}

// Morris' ranking by mu*, and which of the leading units act nonlinearly
// or through interactions (sigma at least mu*: their effects change sign
// or size across the grid).
void print_morris(std::ostream& out, const EnsembleSpec& spec, const Response& response,
                  const designs::MorrisIndices& m) {
  const std::vector<std::string> names = spec.unit_names();
  out << "    drivers (" << (spec.grouped ? "groups, " : "") << "Morris mu* [95 %], " << response.units
      << " per unit of u, from " << m.trajectories << " trajectories): ";
  print_ranking(out, names, m.ranking, m.mu_star, &m.mu_star_ci, "trajectories", {}, false);
  std::string nonlinear;
  for (std::size_t k = 0; k < std::min(m.ranking.order.size(), kRankedShown); ++k) {
    const std::size_t u = m.ranking.order[k];
    if (m.sigma[u] >= m.mu_star[u] && m.mu_star[u] > 0.0)
      nonlinear += (nonlinear.empty() ? "" : ", ") + names[u] + " (sigma " + number(m.sigma[u], "%.3g") + ")";
  }
  if (!nonlinear.empty()) out << "      sigma >= mu*, nonlinear or interacting: " << nonlinear << "\n";
}

// The Sobol' ranking (saltelli), with the blocks it rests on and the
// verdict on N; Morris' (morris); else the ranking by |SRRC| or |Spearman|.
void print_drivers(std::ostream& out, const EnsembleSpec& spec, const Response& response, const ResponseAnswer& a) {
  if (a.morris) return print_morris(out, spec, response, *a.morris);
  if (a.sobol) {
    const SobolIndices& s = *a.sobol;
    if (s.total.empty()) return;
    out << "    drivers (" << (spec.grouped ? "groups, " : "") << "total Sobol' index [95 %], from " << s.base_samples
        << " of " << a.sobol_blocks << " base points): ";
    print_ranking(out, spec.unit_names(), s.ranking, s.total, &s.total_ci, "base points");
    if (a.sobol_blocks > 0 &&
        static_cast<double>(s.base_samples) < kReliableBlockShare * static_cast<double>(a.sobol_blocks))
      out << "      unreliable: failed runs left " << s.base_samples << " of " << a.sobol_blocks
          << " base points complete; failures that depend on the inputs bias what remains\n";
    const IndexVerdict v = index_verdict(s);
    if (std::isfinite(v.widest))
      out << "      is N enough for the indices? " << (v.enough ? "yes" : "no")
          << ": the widest interval of a total index "
          << "that matters is " << number(v.widest, "%.2g") << " (" << spec.unit_names()[v.unit] << ")"
          << (v.enough ? ""
                       : "; about " + number(v.needed, "%.0f") + " base points would make it " +
                             number(kIndexIntervalWidth, "%.1f"))
          << "\n";
    return;
  }
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
