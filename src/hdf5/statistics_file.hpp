// /stats of an ensemble file: per quantity, time x column, the count,
// mean, standard deviation, standard error, minimum, maximum and quantiles
// over the successful samples, and the histogram of the last output time.
#pragma once

#include "hdf5/hdf5.hpp"
#include "job/ensemble_spec.hpp"
#include "job/job.hpp"
#include "output/quantities.hpp"
#include "statistics/ensemble_statistics.hpp"

namespace treedyn::h5 {

void write_statistics(hid_t file, const Job& job, const EnsembleSpec& spec, const ColumnLayout& layout,
                      const statistics::EnsembleStatistics& stats);

}  // namespace treedyn::h5
