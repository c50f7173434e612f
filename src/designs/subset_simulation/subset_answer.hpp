// Subset simulation's answer: its levels' result (P(limit exceeded) with its
// coefficient of variation and interval, each level's threshold, the runs
// made), and the failure region of every run beyond the limit (any level:
// each is a draw of the inputs given the failure). Written into /rare_event
// by subset_file.hpp, printed by subset_summary.cpp.
#pragma once

#include <ostream>

#include "analysis/failure_region.hpp"
#include "designs/subset_simulation/subset_simulation.hpp"
#include "ensemble/response_table.hpp"
#include "job/ensemble_spec.hpp"

namespace treedyn::designs {

struct RareEventAnswer {
  SubsetResult result;
  ensemble::FailureRegion region;
};

// The levels replayed from `table`, and the failure region of its runs.
RareEventAnswer answer_rare_event(const ensemble::EnsembleSpec& spec, const ensemble::ResponseTable& table);

// Its lines in the end-of-run summary: P with its coefficient of variation
// and interval, each level's threshold, the runs made, what crude Monte
// Carlo would have needed for the same coefficient of variation, and what
// makes it fail.
void print_rare_event(std::ostream& out, const ensemble::EnsembleSpec& spec, const RareEventAnswer& answer);

}  // namespace treedyn::designs
