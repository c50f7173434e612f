// How many ranks can a job keep busy before rank 0 limits it? Rank 0
// receives, decodes and writes every rank's records (one writer), so at P
// ranks it takes in P records per sample time; it saturates near
// P = sample CPU / its CPU per record. Its CPU per record was measured per
// example on 2 to 64 oversubscribed ranks (bench/capacity_benchmark.sh,
// BENCHMARKS.md "Rank 0's capacity") and is modelled here from a record's
// encoded size.
#pragma once

#include <cstddef>
#include <ostream>

#include "job/ensemble_spec.hpp"
#include "job/job.hpp"
#include "output/sample_record.hpp"

namespace treedyn::ensemble {

// Rank 0's CPU time per record of `bytes` (encoded, as a sender sends it),
// at 64 ranks (it grows with the ranks: smaller messages), s: a fixed part
// and a part per byte, a least-squares line through the six examples
// (BENCHMARKS.md, "Rank 0's capacity": the fit against each example;
// deflate is most of the per-byte part, and how well a job's rows compress
// moves it).
inline constexpr double kRankZeroFixedSeconds = 7.7e-6;
inline constexpr double kRankZeroSecondsPerByte = 13e-9;
double rank_zero_seconds_per_record(std::size_t bytes);

// A record's encoded size without its stored trajectory: only samples below
// store_trajectories carry one, so rank 0's steady cost is for records
// without (a trajectory can be a hundred times the rest).
std::size_t typical_record_bytes(const SampleRecord& record);

struct Capacity {
  std::size_t record_bytes = 0;  // one sample's encoded record
  double record_seconds = 0.0;   // rank 0's CPU per record
  double sample_seconds = 0.0;   // one sample's CPU (at least, when `sample_cut`)
  bool sample_cut = false;       // the timed sample ran past the budget and was stopped
  double ranks() const { return sample_seconds / record_seconds; }
};

// Times sample 0 on this thread's CPU, up to 3 times within `budget`
// seconds (the nominal run included), the fastest, and models rank 0's
// cost for its record; a sample over the budget is stopped there.
Capacity measure_capacity(const Job& job, const EnsembleSpec& spec, double budget = 5.0);

// "rank 0 takes in about X records/s of this job's size (B bytes); at S ms
// per sample (timed now) this job scales to about Z ranks before rank 0
// limits it".
void print_capacity(std::ostream& out, const Capacity& c, const char* timed);

}  // namespace treedyn::ensemble
