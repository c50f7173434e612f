// Before any work: does what every rank of a node will allocate fit in the
// memory that node has? Ranks of one node are found with
// MPI_Comm_split_type(SHARED); the memory available is MemAvailable
// (/proc/meminfo), lowered to a cgroup v2 limit (memory.max - memory.current)
// when there is one, or TREEDYN_MEMORY_AVAILABLE (bytes) when set: for
// schedulers whose limits are not visible as a cgroup, and for tests.
#pragma once

#include <mpi.h>

namespace treedyn::parallel {

// Collective. Returns false on every rank when some node lacks the memory;
// rank 0 of that node has printed what is needed and what is there.
bool memory_fits(MPI_Comm comm, double bytes_per_rank);

}  // namespace treedyn::parallel
