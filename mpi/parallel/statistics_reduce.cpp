#include "parallel/statistics_reduce.hpp"

#include <vector>

namespace treedyn::parallel {
namespace {

constexpr int kTagPiece = 1;

void send_state(MPI_Comm comm, int to, const statistics::EnsembleStatistics& stats) {
  std::vector<char> piece;
  for (std::size_t k = 0; k < stats.state_pieces(); ++k) {
    piece.clear();
    ByteWriter out(piece);
    stats.write_state_piece(k, out);
    MPI_Send(piece.data(), static_cast<int>(piece.size()), MPI_BYTE, to, kTagPiece, comm);
  }
}

void add_state(MPI_Comm comm, int from, statistics::EnsembleStatistics& stats) {
  std::vector<char> piece;
  for (std::size_t k = 0; k < stats.state_pieces(); ++k) {
    MPI_Status status;
    MPI_Probe(from, kTagPiece, comm, &status);
    int bytes = 0;
    MPI_Get_count(&status, MPI_BYTE, &bytes);
    piece.resize(static_cast<std::size_t>(bytes));
    MPI_Recv(piece.data(), bytes, MPI_BYTE, from, kTagPiece, comm, MPI_STATUS_IGNORE);
    ByteReader in(piece, "the statistics of rank " + std::to_string(from));
    stats.add_state_piece(k, in);
  }
}

}  // namespace

void reduce_statistics(MPI_Comm comm, statistics::EnsembleStatistics& stats) {
  MPI_Comm tree;  // its own communicator: no other message can match
  MPI_Comm_dup(comm, &tree);
  int rank = 0, size = 1;
  MPI_Comm_rank(tree, &rank);
  MPI_Comm_size(tree, &size);
  for (int step = 1; step < size; step *= 2) {
    if (rank % (2 * step) != 0) {
      send_state(tree, rank - step, stats);
      break;
    }
    if (rank + step < size) add_state(tree, rank + step, stats);
  }
  MPI_Comm_free(&tree);
}

}  // namespace treedyn::parallel
