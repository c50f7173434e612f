// Subset simulation's answer in the ensemble file: /rare_event/<response>.
#pragma once

#include "designs/subset_simulation/subset_answer.hpp"
#include "hdf5/hdf5.hpp"
#include "job/ensemble_spec.hpp"

namespace treedyn::designs {

// /rare_event/<response>: the estimate, its cov and interval, each level's
// threshold, conditional probability, gamma, acceptance rate and runs, and
// the failure region of every run beyond the limit.
void write_rare_event(hid_t file, const ensemble::EnsembleSpec& spec, const designs::SubsetSettings& settings,
                      const RareEventAnswer& answer);

}  // namespace treedyn::designs
