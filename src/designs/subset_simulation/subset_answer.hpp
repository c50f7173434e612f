// Subset simulation's answer for the whole run (designs/design_answer.hpp):
// its levels' result (P(limit exceeded) with its coefficient of variation
// and interval, each level's threshold, the runs made), and the failure
// region of every run beyond the limit (any level: each is a draw of the
// inputs given the failure). Computed in subset_answer.cpp, printed by
// subset_summary.cpp, written into /rare_event and /samples by subset_file.cpp.
#pragma once

#include <memory>
#include <ostream>
#include <string>

#include "analysis/failure_region.hpp"
#include "designs/design_answer.hpp"
#include "designs/subset_simulation/subset_simulation.hpp"
#include "ensemble/response_table.hpp"
#include "job/ensemble_spec.hpp"

namespace treedyn::designs {

class RareEventAnswer final : public RunAnswer {
 public:
  RareEventAnswer(SubsetResult levels, analysis::FailureRegion beyond)
      : result(std::move(levels)), region(std::move(beyond)) {}

  // Which level ended the run, and why.
  std::string stop_reason() const override;
  // P with its coefficient of variation and interval, each level's
  // threshold, the runs made, what crude Monte Carlo would have needed for
  // the same coefficient of variation, and what makes it fail.
  void print(std::ostream& out, const EnsembleSpec& spec) const override;
  // /rare_event/<response>: the estimate, its cov and interval, each level's
  // threshold, conditional probability, gamma, acceptance rate and runs, and
  // the failure region; /samples/level, chain and state of every run kept.
  void write(AnswerWriter& root, AnswerWriter& samples, const EnsembleSpec& spec, std::size_t rows) const override;

  SubsetResult result;
  analysis::FailureRegion region;
};

// The levels replayed from `table`, and the failure region of its runs.
std::unique_ptr<const RareEventAnswer> answer_rare_event(const EnsembleSpec& spec,
                                                         const ensemble::ResponseTable& table);

}  // namespace treedyn::designs
