// What an ensemble run did, for the file's root attributes and the
// end-of-run summary: samples ok and failed, ranks, wall time, and each
// rank's peak memory, samples, busy time and time writing records.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace treedyn::ensemble {

struct RunSummary {
  std::uint64_t ok = 0, failed = 0;
  int ranks = 1;
  double wall_seconds = 0.0;
  std::vector<double> peak_rss_mib;         // per rank (getrusage maximum resident set)
  std::vector<long long> samples_per_rank;  // samples each rank integrated
  // Their sum: the samples this run integrated itself (not those restored or merged).
  std::uint64_t samples_run_here() const {
    std::uint64_t n = 0;
    for (long long s : samples_per_rank) n += static_cast<std::uint64_t>(s);
    return n;
  }
  std::vector<double> busy_seconds;     // time each rank spent on samples: integrating, recording, updating its
                                        // statistics, checkpointing, sending
  std::vector<double> writing_seconds;  // time each rank spent writing records: rank 0 receives and writes them all
  // The same two as CPU time of the rank's main thread, which oversubscribed
  // ranks do not inflate (rank 0's capacity), and each rank's whole CPU time.
  std::vector<double> busy_cpu_seconds, writing_cpu_seconds, cpu_seconds;
  std::uint64_t samples_used = 0;  // the runs the answers count ([ensemble.stop]: <= samples)
  // Rows of a unit (a whole chunk a sender compressed itself), 0: none; and
  // the samples whose rows came that way.
  std::uint64_t unit_rows = 0, samples_in_units = 0;
  double unit_storing_cpu_seconds = 0.0;  // rank 0's CPU storing them (of its record writing)
  std::string stop_reason;                // why the run ended where it did
};

}  // namespace treedyn::ensemble
