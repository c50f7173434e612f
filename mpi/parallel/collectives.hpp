// Small collectives the driver's phases share: vectors broadcast in chunks
// (MPI counts are ints), element-wise all-reductions, and the agreement of
// every rank on one flag, count or exit code.
#pragma once

#include <mpi.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace treedyn::parallel {

// The same vector on every rank (rank 0's).
template <class T>
void broadcast(MPI_Comm comm, std::vector<T>& v) {
  unsigned long long size = v.size();
  MPI_Bcast(&size, 1, MPI_UNSIGNED_LONG_LONG, 0, comm);
  v.resize(size);
  constexpr std::size_t kChunk = std::size_t{1} << 24;
  const std::size_t bytes = size * sizeof(T);
  auto* data = reinterpret_cast<char*>(v.data());
  for (std::size_t first = 0; first < bytes; first += kChunk)
    MPI_Bcast(data + first, static_cast<int>(std::min(kChunk, bytes - first)), MPI_BYTE, 0, comm);
}

// Rank 0's value on every rank.
inline int broadcast(MPI_Comm comm, int value) {
  MPI_Bcast(&value, 1, MPI_INT, 0, comm);
  return value;
}
inline std::uint64_t broadcast(MPI_Comm comm, std::uint64_t value) {
  MPI_Bcast(&value, 1, MPI_UINT64_T, 0, comm);
  return value;
}

// Element-wise all-reduce of doubles in chunks.
inline void all_reduce(MPI_Comm comm, std::vector<double>& v, MPI_Op op) {
  constexpr std::size_t kChunk = std::size_t{1} << 26;
  for (std::size_t first = 0; first < v.size(); first += kChunk)
    MPI_Allreduce(MPI_IN_PLACE, v.data() + first, static_cast<int>(std::min(kChunk, v.size() - first)), MPI_DOUBLE, op,
                  comm);
}

inline std::uint64_t sum_over_ranks(MPI_Comm comm, std::uint64_t mine) {
  MPI_Allreduce(MPI_IN_PLACE, &mine, 1, MPI_UINT64_T, MPI_SUM, comm);
  return mine;
}

inline int max_over_ranks(MPI_Comm comm, int mine) {
  MPI_Allreduce(MPI_IN_PLACE, &mine, 1, MPI_INT, MPI_MAX, comm);
  return mine;
}

inline bool any_rank(MPI_Comm comm, bool mine) { return max_over_ranks(comm, mine ? 1 : 0) != 0; }

}  // namespace treedyn::parallel
