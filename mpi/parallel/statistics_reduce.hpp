// Sums ensemble statistics over all ranks onto rank 0: a binomial tree in
// which each rank sends its state (in pieces, EnsembleStatistics::
// write_state_piece) to its parent, which adds it. Every part is an integer
// sum, a min or a max, so the result is the same for any number of ranks.
#pragma once

#include <mpi.h>

#include "statistics/ensemble_statistics.hpp"

namespace treedyn::parallel {

void reduce_statistics(MPI_Comm comm, statistics::EnsembleStatistics& stats);

}  // namespace treedyn::parallel
