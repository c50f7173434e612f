#include "hdf5/answers_file.hpp"

#include <cstdint>
#include <optional>
#include <string>

#include "designs/design_rules.hpp"
#include "hdf5/answer_datasets.hpp"
#include "hdf5/answer_group_writer.hpp"
#include "hdf5/described.hpp"

namespace treedyn::h5 {
namespace {

// /responses/<name>/exceedance: the limit state's probability, its interval,
// what the failed samples can change, and the failure region.
void write_exceedance(hid_t g, const EnsembleSpec& spec, const Response& response, const analysis::ResponseAnswer& a) {
  const analysis::Exceedance& e = *a.exceedance;
  Handle x = create_group(g, "exceedance");
  write_attribute(x.id(), "description",
                  "limit state: value " + std::string(name(response.fail_if)) +
                      " the limit, over the successful samples; failed samples are counted "
                      "beside it (survivor bias)");
  write_attribute(x.id(), "limit", response.limit);
  write_attribute(x.id(), "fail_if", std::string(name(response.fail_if)));
  write_described_scalar(x.id(), "probability", e.probability, "1", "exceeded / successful");
  write_described_scalar(x.id(), "count", e.exceeded, "1", "successful samples beyond the limit");
  write_described_scalar(x.id(), "successful", e.successful, "1", "successful samples (the denominator)");
  write_described_scalar(x.id(), "failed", e.failed, "1", "samples that failed and are not in the denominator");
  write_pair(x.id(), "interval", e.interval.low, e.interval.high,
             "95 % Wilson score interval of the probability: low, high");
  write_pair(x.id(), "with_failed", e.with_failed.low, e.with_failed.high,
             "P over the successful and failed samples with every failed one counted as not exceeding (low) "
             "and as exceeding (high): what the failures can change");
  if (a.failure_region) write_failure_region(x.id(), spec, *a.failure_region, "the counted runs beyond the limit");
}

// /responses/<name>/convergence: the answers of the prefixes.
void write_convergence(hid_t g, const EnsembleSpec& spec, const Response& response, const analysis::ResponseAnswer& a) {
  std::vector<double> table;
  for (const analysis::ConvergencePoint& p : a.convergence)
    table.insert(table.end(), {static_cast<double>(p.samples), static_cast<double>(p.used), p.mean, p.sem,
                               p.probability, p.interval.low, p.interval.high});
  Handle c = write_matrix(g, "convergence", table, a.convergence.size(), 7);
  describe(c.id(), "per column: the 'column_units' attribute",
           std::string("answers from samples 0 .. m-1 for m = 1, 2, 4, ... and N, in sample-index order ") +
               (designs::rules_of(spec.design).nested_prefixes()
                    ? "(this design's first runs are a design of their own: a convergence)"
                    : "(this design's first runs are not a design of their own: the last row is its answer, the "
                      "others a rough guide)"),
           {"samples", "used", "mean", "sem", "exceedance_probability", "wilson_low", "wilson_high"});
  write_attribute(c.id(), "column_units",
                  std::vector<std::string>{"1", "1", response.units, response.units, "1", "1", "1"});
}

// " (saltelli: the A and B runs)": which runs the answers count, where not all.
std::string counted_runs(const EnsembleSpec& spec) {
  const std::string_view note = designs::rules_of(spec.design).counted_runs_note();
  return note.empty() ? "" : " (" + std::string(note) + ")";
}

void write_response_answer(hid_t parent, const EnsembleSpec& spec, const Response& response,
                           const analysis::ResponseAnswer& a) {
  Handle g = create_group(parent, response.name);
  write_attribute(g.id(), "units", response.units);
  write_attribute(g.id(), "quantity", response.quantity);
  write_attribute(g.id(), "column", response.column);
  write_attribute(g.id(), "reduce", std::string(name(response.reduce)));
  write_described_scalar(g.id(), "mean", a.mean, response.units, "mean over the successful samples with finite values");
  write_described_scalar(g.id(), "std", a.std, response.units, "sample standard deviation (n - 1)");
  write_described_scalar(g.id(), "sem", a.sem, response.units, "standard error of the mean, std / sqrt(used)");
  write_described_scalar(g.id(), "used", a.used, "1", "successful samples with a finite value");
  write_described_scalar(g.id(), "not_finite", a.not_finite, "1",
                         "successful samples with +-inf (a level never crossed)");
  write_described_scalar(g.id(), "failed", a.failed, "1", "samples that failed (left out)");
  if (a.exceedance) write_exceedance(g.id(), spec, response, a);
  write_convergence(g.id(), spec, response, a);
}

void write_sensitivity(hid_t parent, const EnsembleSpec& spec, const Response& response,
                       const analysis::ResponseAnswer& a) {
  const std::vector<std::string> inputs = spec.input_names();
  Handle sg = create_group(parent, response.name);
  write_attribute(sg.id(), "description", std::string(designs::rules_of(spec.design).sensitivity_description()));
  write_per_input(sg.id(), "spearman", a.ranks.spearman, "1",
                  "Spearman rank correlation of each input with the response", inputs);
  write_per_input(sg.id(), "srrc", a.ranks.srrc, "1",
                  "standardised rank regression coefficient of each input (see the r_squared attribute)", inputs);
  write_attribute(sg.id(), "rank_r_squared", a.ranks.r_squared);
  write_attribute(sg.id(), "rank_samples", static_cast<long long>(a.ranks.samples));
  write_ranking(sg.id(), "rank_ranking", a.ranks.ranking, a.ranks.ranked_by_srrc ? "|SRRC|" : "|Spearman|", inputs,
                "runs");
  write_interval_matrix(sg.id(), "rank_measure_ci", a.ranks.measure_ci,
                        std::string("95 % bootstrap interval of each input's ") +
                            (a.ranks.ranked_by_srrc ? "|SRRC|" : "|Spearman|") + " (the rank ranking's measure)",
                        inputs, "input");
  if (a.design) {
    GroupAnswerWriter writer(sg.id());
    a.design->write(writer, spec, response);
  }
}

}  // namespace

void write_answers(hid_t file, const EnsembleSpec& spec, const std::vector<analysis::ResponseAnswer>& answers) {
  if (answers.empty()) return;
  Handle responses = create_group(file, "responses");
  write_attribute(responses.id(), "description",
                  "per named response ([[ensemble.response]]): mean and standard error over the successful "
                  "samples with finite values" +
                      counted_runs(spec) + ", the exceedance of its limit, and their convergence");
  std::optional<Handle> sensitivity;
  if (spec.input_dimensions() > 0) {
    sensitivity = create_group(file, "sensitivity");
    write_attribute(sensitivity->id(), "description",
                    std::string("per response, how much each sampled input (/samples/inputs "
                                "columns) drives it"));
  }
  for (std::size_t r = 0; r < answers.size(); ++r) {
    write_response_answer(responses.id(), spec, spec.responses[r], answers[r]);
    if (sensitivity) write_sensitivity(sensitivity->id(), spec, spec.responses[r], answers[r]);
  }
}

void write_tolerance_check(hid_t file, const EnsembleSpec& spec, const statistics::ToleranceCheck& check) {
  if (check.empty()) return;
  Handle g = create_group(file, "integration_check");
  write_attribute(g.id(), "description",
                  "is the integration accurate enough for the answers? The pilot's first samples (attribute "
                  "'samples') run again with rtol and atol " +
                      std::to_string(statistics::kToleranceFactor).substr(0, 4) +
                      " times the job's: per response, the largest change against its spread over the pilot");
  write_attribute(g.id(), "rtol", check.rtol);
  write_attribute(g.id(), "atol", check.atol);
  write_attribute(g.id(), "rerun_rtol", check.rtol * statistics::kToleranceFactor);
  write_attribute(g.id(), "rerun_atol", check.atol * statistics::kToleranceFactor);
  const std::vector<long long> samples(check.samples.begin(), check.samples.end());
  const hsize_t rerun[1] = {samples.size()};
  describe(write_array(g.id(), "samples", H5T_NATIVE_LLONG, samples.data(), rerun).id(), "1",
           "the pilot samples rerun that succeeded at both tolerances", {});
  std::vector<std::string> names, units, verdicts;
  std::vector<double> ratio;
  for (std::size_t r = 0; r < spec.responses.size(); ++r) {
    names.push_back(spec.responses[r].name);
    units.push_back(spec.responses[r].units);
    verdicts.push_back(statistics::describe_verdict(check, r));
    ratio.push_back(check.change[r] / check.spread[r]);
  }
  Handle c = write_vector(g.id(), "change", check.change);
  describe(c.id(), "per column: the 'column_units' attribute", "the largest |y(tight) - y| over the samples rerun",
           names);
  write_attribute(c.id(), "column_units", units);
  Handle s = write_vector(g.id(), "spread", check.spread);
  describe(s.id(), "per column: the 'column_units' attribute",
           "standard deviation (n - 1) of the response over the pilot's successful samples", names);
  write_attribute(s.id(), "column_units", units);
  write_per_input(g.id(), "ratio", ratio, "1",
                  "change / spread: above 0.1 too loose, below 0.001 far tighter than needed", names);
  write_attribute(g.id(), "verdicts", verdicts);
}

}  // namespace treedyn::h5
