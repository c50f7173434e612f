// A shared queue of sample indices: a counter in an MPI window on rank 0,
// advanced with an atomic fetch-and-add. Any rank, rank 0 included, takes the
// next block of indices when it is free, so fast ranks take more blocks and
// nobody idles while work remains.
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

  // The next block; false when the queue is empty.
  bool next(std::uint64_t& begin, std::uint64_t& end);

 private:
  MPI_Win window_ = MPI_WIN_NULL;
  std::uint64_t* counter_ = nullptr;
  std::uint64_t end_, block_;
};

}  // namespace treedyn::parallel
