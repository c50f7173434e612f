#include "parallel/work_queue.hpp"

#include <algorithm>
#include <exception>

namespace treedyn::parallel {

WorkQueue::WorkQueue(MPI_Comm comm, std::uint64_t first, std::uint64_t end, std::uint64_t block)
    : end_(end), block_(block) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const MPI_Aint bytes = rank == 0 ? static_cast<MPI_Aint>(2 * sizeof(std::uint64_t)) : 0;
  MPI_Win_allocate(bytes, sizeof(std::uint64_t), MPI_INFO_NULL, comm, &counter_, &window_);
  if (rank == 0) {  // a local store inside an exclusive epoch: visible to RMA after unlock
    MPI_Win_lock(MPI_LOCK_EXCLUSIVE, 0, 0, window_);
    counter_[0] = first;
    counter_[1] = 0;
    MPI_Win_unlock(0, window_);
  }
  MPI_Barrier(comm);  // the counter is set before anyone takes from it
  MPI_Win_lock_all(MPI_MODE_NOCHECK, window_);
}

WorkQueue::~WorkQueue() {
  // Freeing the window is collective: while an exception unwinds on this rank
  // the others would wait in it forever, so leave it to MPI_Abort instead.
  if (std::uncaught_exceptions() > 0) return;
  MPI_Win_unlock_all(window_);
  MPI_Win_free(&window_);
}

bool WorkQueue::next(std::uint64_t& begin, std::uint64_t& end) {
  if (interrupted()) return false;
  std::uint64_t taken = 0;
  MPI_Fetch_and_op(&block_, &taken, MPI_UINT64_T, 0, 0, MPI_SUM, window_);
  MPI_Win_flush(0, window_);
  if (taken >= end_) return false;
  begin = taken;
  end = std::min(end_, taken + block_);
  return true;
}

void WorkQueue::interrupt() {
  const std::uint64_t one = 1;
  std::uint64_t previous = 0;
  MPI_Fetch_and_op(&one, &previous, MPI_UINT64_T, 0, 1, MPI_REPLACE, window_);
  MPI_Win_flush(0, window_);
  interrupted_ = true;
}

bool WorkQueue::interrupted() {
  if (interrupted_) return true;
  std::uint64_t flag = 0, unused = 0;
  MPI_Fetch_and_op(&unused, &flag, MPI_UINT64_T, 0, 1, MPI_NO_OP, window_);
  MPI_Win_flush(0, window_);
  interrupted_ = flag != 0;
  return interrupted_;
}

}  // namespace treedyn::parallel
