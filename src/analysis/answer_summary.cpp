#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "analysis/answers.hpp"
#include "analysis/summary_text.hpp"
#include "designs/design_rules.hpp"

namespace treedyn::analysis {
namespace {

// Inputs that are entries of a list target (a sea state's phases).
std::vector<bool> list_entries(const EnsembleSpec& spec) {
  std::vector<bool> hidden;
  for (const sampling::Perturbation& p : spec.perturbations)
    for (int k = 0; k < p.dimensions(); ++k) hidden.push_back(p.kind == sampling::Perturbation::Kind::parameter_list);
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

}  // namespace

void print_response_summary(std::ostream& out, const EnsembleSpec& spec, const std::vector<ResponseAnswer>& answers,
                            const statistics::ToleranceCheck& tolerance) {
  if (answers.empty()) return;
  const std::string_view counted = designs::rules_of(spec.design).counted_runs_note();
  out << "responses: mean +- standard error (successful samples with finite values" << (counted.empty() ? "" : "; ")
      << counted << ")\n";
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
    if (r < tolerance.change.size()) out << "    integration: " << statistics::describe_verdict(tolerance, r) << "\n";
    if (designs::rules_of(spec.design).answers_probability(spec, r) && a.exceedance) {
      out << "    P: " << name(spec.design) << "'s answer, below (the runs counted above have "
          << a.exceedance->exceeded << " of " << a.exceedance->successful << " beyond the limit)\n";
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

}  // namespace treedyn::analysis
