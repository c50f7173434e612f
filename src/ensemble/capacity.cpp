#include "ensemble/capacity.hpp"

#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "ensemble/sample_runner.hpp"
#include "persistence/record_codec.hpp"

namespace treedyn::ensemble {
namespace {

double thread_cpu() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct OverBudget {};

}  // namespace

double rank_zero_seconds_per_record(std::size_t bytes) {
  // A fixed part per record (the message's share, the response table) and
  // a part per byte (decoding, the scatter into every per-sample dataset,
  // deflate).
  return kRankZeroFixedSeconds + kRankZeroSecondsPerByte * static_cast<double>(bytes);
}

std::size_t typical_record_bytes(const SampleRecord& record) {
  return encoded_size(record) - record.trajectory.size() * sizeof(double);
}

Capacity measure_capacity(const Job& job, const EnsembleSpec& spec, double budget) {
  SampleRunner runner(job, spec);
  std::vector<double> trajectory;
  const double start = thread_cpu();
  runner.run(0, true, trajectory);
  Capacity c;
  c.sample_seconds = std::numeric_limits<double>::infinity();
  // The fastest of up to 3 runs of sample 0 within the budget: the first
  // runs touch memory for the first time and run slower.
  for (int k = 0; k < 3 && (k == 0 || thread_cpu() - start < budget); ++k) {
    const double from = thread_cpu();
    SampleRecord record;
    try {
      record = runner.run(0, false, trajectory, [&] {
        if (thread_cpu() - start > budget) throw OverBudget{};
      });
    } catch (const OverBudget&) {
      c.sample_cut = k == 0;
      record = runner.failed_record(0, SampleStatus::integration_failed, "");
    }
    if (k == 0 || !c.sample_cut) c.sample_seconds = std::min(c.sample_seconds, thread_cpu() - from);
    c.record_bytes = std::max(c.record_bytes, typical_record_bytes(record));
    if (c.sample_cut) break;
  }
  c.record_seconds = rank_zero_seconds_per_record(c.record_bytes);
  return c;
}

void print_capacity(std::ostream& out, const Capacity& c, const char* timed) {
  char line[400];
  std::snprintf(line, sizeof line,
                "rank 0's capacity: it takes in about %.0f records/s of this job's size (%zu bytes each, "
                "measured on the development machine: BENCHMARKS.md); at %s%.3g ms per sample (%s) this job "
                "scales to %sabout %.0f ranks before rank 0 limits it",
                1.0 / c.record_seconds, c.record_bytes, c.sample_cut ? "more than " : "", c.sample_seconds * 1e3, timed,
                c.sample_cut ? "more than " : "", std::floor(c.ranks()));
  out << line << "\n";
}

}  // namespace treedyn::ensemble
