#include "parallel/memory_check.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <limits>
#include <string>

namespace treedyn::parallel {
namespace {

double read_number(const std::string& path) {
  std::ifstream in(path);
  std::string word;
  if (!(in >> word) || word == "max") return std::numeric_limits<double>::infinity();
  return std::strtod(word.c_str(), nullptr);
}

// Bytes this node can still give, as seen from this process.
double available_bytes() {
  if (const char* given = std::getenv("TREEDYN_MEMORY_AVAILABLE")) return std::strtod(given, nullptr);
  double available = std::numeric_limits<double>::infinity();
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kib = 0.0;
  std::string unit;
  while (meminfo >> key >> kib >> unit)
    if (key == "MemAvailable:") available = kib * 1024.0;
  const double limit = read_number("/sys/fs/cgroup/memory.max");
  if (limit < std::numeric_limits<double>::infinity()) {
    const double used = read_number("/sys/fs/cgroup/memory.current");
    if (used < limit) available = std::min(available, limit - used);
  }
  return available;
}

std::string gib(double bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f GiB", bytes / (1024.0 * 1024.0 * 1024.0));
  return text;
}

}  // namespace

bool memory_fits(MPI_Comm comm, double bytes_per_rank) {
  MPI_Comm node = MPI_COMM_NULL;
  MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  int local_rank = 0, local_size = 1;
  MPI_Comm_rank(node, &local_rank);
  MPI_Comm_size(node, &local_size);
  MPI_Comm_free(&node);
  int fits = 1;
  if (local_rank == 0) {
    const double needed = bytes_per_rank * local_size, available = available_bytes();
    if (needed > available) {
      char host[256] = "this host";
      gethostname(host, sizeof host - 1);
      std::cerr << "error: not enough memory on " << host << ": the statistics need about " << gib(bytes_per_rank)
                << " per rank (--check prints it), " << local_size << " rank(s) there: " << gib(needed) << ", but only "
                << gib(available)
                << " are available; use fewer ranks per node, fewer histogram_bins, output times or quantities\n";
      fits = 0;
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, &fits, 1, MPI_INT, MPI_MIN, comm);
  return fits != 0;
}

}  // namespace treedyn::parallel
