#include "parallel/statistics_reduce.hpp"

#include <algorithm>
#include <cstring>

#include "parallel/mpi_handles.hpp"

namespace treedyn::parallel {
namespace {

using ensemble::wide;

// MPI user operation: element-wise sum of 128-bit integers (buffers may be
// unaligned, hence memcpy).
void sum_wide(void* in, void* inout, int* length, MPI_Datatype*) {
  auto* a = static_cast<const char*>(in);
  auto* b = static_cast<char*>(inout);
  for (int k = 0; k < *length; ++k) {
    wide x, y;
    std::memcpy(&x, a + k * sizeof(wide), sizeof(wide));
    std::memcpy(&y, b + k * sizeof(wide), sizeof(wide));
    y += x;
    std::memcpy(b + k * sizeof(wide), &y, sizeof(wide));
  }
}

// In chunks: MPI counts are ints, the arrays may be longer.
template <class T>
void reduce(MPI_Comm comm, std::vector<T>& v, MPI_Datatype type, MPI_Op op) {
  constexpr std::size_t kChunk = std::size_t{1} << 26;
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  for (std::size_t first = 0; first < v.size(); first += kChunk) {
    const int n = static_cast<int>(std::min(kChunk, v.size() - first));
    if (rank == 0)
      MPI_Reduce(MPI_IN_PLACE, v.data() + first, n, type, op, 0, comm);
    else
      MPI_Reduce(v.data() + first, nullptr, n, type, op, 0, comm);
  }
}

}  // namespace

void reduce_statistics(MPI_Comm comm, ensemble::EnsembleStatistics& s) {
  MPI_Datatype raw;
  MPI_Type_contiguous(static_cast<int>(sizeof(wide)), MPI_BYTE, &raw);
  const Datatype wide_type(raw);
  const Op wide_sum(sum_wide, true);
  reduce(comm, s.sums(), wide_type, wide_sum);
  reduce(comm, s.square_sums(), wide_type, wide_sum);
  reduce(comm, s.minima(), MPI_DOUBLE, MPI_MIN);
  reduce(comm, s.maxima(), MPI_DOUBLE, MPI_MAX);
  reduce(comm, s.counts(), MPI_UINT32_T, MPI_SUM);
  reduce(comm, s.out_of_range_counts(), MPI_UINT64_T, MPI_SUM);
  std::vector<std::uint64_t> samples{s.sample_count()};
  reduce(comm, samples, MPI_UINT64_T, MPI_SUM);
  s.sample_count() = samples[0];
}

}  // namespace treedyn::parallel
