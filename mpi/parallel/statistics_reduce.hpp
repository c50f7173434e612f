// Sums ensemble statistics over all ranks onto rank 0. Every part is an
// integer sum, a min or a max, so the result is the same for any number of
// ranks and any reduction order.
#pragma once

#include <mpi.h>

#include "ensemble/statistics.hpp"

namespace treedyn::parallel {

void reduce_statistics(MPI_Comm comm, ensemble::EnsembleStatistics& stats);

}  // namespace treedyn::parallel
