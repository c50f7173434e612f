// A shared queue of sample indices: a counter in an MPI window on rank 0,
// advanced with an atomic fetch-and-add. Any rank, rank 0 included, takes the
// next block of indices when it is free, so fast ranks take more blocks and
// nobody idles while work remains. A second word in the window is the
// interruption flag: a rank that got SIGTERM raises it, and every rank sees
// it at its next sample and stops too, so no rank is left waiting.
#pragma once

#include <mpi.h>

#include <cstdint>

namespace treedyn::parallel {

class WorkQueue {
 public:
  // Hands out [first, end) in blocks of `block`. Collective over `comm`.
  WorkQueue(MPI_Comm comm, std::uint64_t first, std::uint64_t end, std::uint64_t block);
  ~WorkQueue();
  WorkQueue(const WorkQueue&) = delete;
  WorkQueue& operator=(const WorkQueue&) = delete;

  // The next block; false when the queue is empty or interrupted.
  bool next(std::uint64_t& begin, std::uint64_t& end);
  // Raises the flag for everyone (once is enough).
  void interrupt();
  // Whether any rank raised it (one small RMA read).
  bool interrupted();

 private:
  MPI_Win window_ = MPI_WIN_NULL;
  std::uint64_t* counter_ = nullptr;  // [next index, interruption flag] on rank 0
  bool interrupted_ = false;
  std::uint64_t end_, block_;
};

}  // namespace treedyn::parallel
