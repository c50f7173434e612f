// The answers of an ensemble file, whoever computed them (a run, a merge):
// /responses (each response's mean, exceedance, what the failed samples can
// change and the failure region, convergence), /sensitivity (rank measures
// and their ranking, then the design's own answer, which writes itself
// through answer_group_writer.hpp: designs/design_answer.hpp). A design's
// answer for the whole run (subset simulation's /rare_event) is written by
// EnsembleWriter::write_run_answer through the same writer.
#pragma once

#include <vector>

#include "analysis/answers.hpp"
#include "hdf5/hdf5.hpp"
#include "job/ensemble_spec.hpp"
#include "statistics/tolerance_check.hpp"

namespace treedyn::h5 {

// /responses and, with sampled inputs, /sensitivity: one group per response.
void write_answers(hid_t file, const EnsembleSpec& spec, const std::vector<analysis::ResponseAnswer>& answers);

// /integration_check: the pilot's tolerance check (nothing without responses).
void write_tolerance_check(hid_t file, const EnsembleSpec& spec, const statistics::ToleranceCheck& check);

}  // namespace treedyn::h5
