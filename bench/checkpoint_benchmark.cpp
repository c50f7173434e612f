// What checkpoints cost, on every shipped example scaled to 10,000 samples.
//
// A rank's checkpoint (src/persistence/checkpoint.hpp) appends the records
// finished since the last one and rewrites its statistics, then fsyncs.
// Measured here, per example, in one run: the time of one sample (median of
// 3), the fixed cost of one checkpoint (the statistics written and flushed;
// median of 5), the same without the flush (what a stop signal costs: the
// deadline is the launcher's SIGKILL, 0.2 s after its SIGTERM under Open
// MPI 5), and the cost of appending 10,000 real records of that example.
// The statistics are at their largest: every histogram bin of every entry
// holds a sample (dense counts). At the default --checkpoint-every 300 s on
// P ranks, a rank integrates W = 10,000 t_sample / P seconds, writes
// floor(W / 300) + 1 checkpoints (the last on a signal) and appends
// 10,000 / P records, so the overhead is (checkpoints x fixed + appends / P) / W.
//
//   checkpoint_benchmark [DIR] [RANKS]    (DIR: where to write, default /tmp)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "ensemble/sample_runner.hpp"
#include "job/ensemble_spec.hpp"
#include "job/sample_job.hpp"
#include "persistence/checkpoint.hpp"
#include "statistics/ensemble_statistics.hpp"
#include "timing.hpp"

namespace fs = std::filesystem;

namespace {

using namespace treedyn;
using bench::Clock;
using bench::median;
using bench::seconds_since;

constexpr int kSamples = 10000;
constexpr double kInterval = 300.0;  // the default --checkpoint-every, seconds

// One example's costs, in seconds and bytes.
struct CheckpointCosts {
  double sample = 0, fixed = 0, unflushed = 0, append = 0, state_bytes = 0, record_bytes = 0;
};

// A rank's statistics with every histogram bin of every entry filled: the
// state at its largest.
statistics::EnsembleStatistics filled_statistics(const ensemble::SampleRunner& runner, const EnsembleSpec& spec,
                                                 const std::vector<double>& nominal) {
  const std::size_t columns = runner.layout().columns, entries = nominal.size();
  std::vector<double> scale(columns, 1.0), zero(entries, 0.0), row(entries);
  statistics::EnsembleStatistics stats(runner.times(), columns, spec.histogram_bins,
                                       statistics::calibrate(nominal, zero, zero, scale, columns, spec.histogram_bins));
  const statistics::Calibration& c = stats.calibration();
  for (int b = 0; b < spec.histogram_bins; ++b) {
    for (std::size_t e = 0; e < entries; ++e) row[e] = c.low[e] + (b + 0.5) * c.width[e];
    stats.add_sample(row);
  }
  return stats;
}

// Ten saves of one new record each, alternately flushed and not; then
// kSamples records appended, as a run appends them (only samples below
// store_trajectories carry their trajectory: the crane's 6 are 350 KB each).
void measure_saves(const fs::path& dir, const Job& job, const EnsembleSpec& spec,
                   const statistics::EnsembleStatistics& stats, SampleRecord record, const std::vector<double>& stored,
                   CheckpointCosts& costs) {
  const persistence::RunIdentity id = persistence::run_identity(job.text, "benchmark");
  persistence::RankCheckpoint checkpoint(dir, id, 0, "rank0");
  std::vector<double> fixed, unflushed;
  for (int k = 0; k < 10; ++k) {
    checkpoint.add(record);  // one new record: a save with nothing new is skipped
    const auto t0 = Clock::now();
    checkpoint.save(stats, k % 2 == 0 ? process::AtomicFile::Sync::yes : process::AtomicFile::Sync::no);
    (k % 2 == 0 ? fixed : unflushed).push_back(seconds_since(t0));
  }
  costs.fixed = median(fixed);
  costs.unflushed = median(unflushed);
  costs.state_bytes = static_cast<double>(fs::file_size(dir / "part-0-rank0.state"));
  const auto t0 = Clock::now();
  for (int k = 0; k < kSamples; ++k) {
    record.index = static_cast<std::uint64_t>(k);
    if (record.index < spec.store_trajectories)
      record.trajectory = stored;
    else
      record.trajectory.clear();
    checkpoint.add(record);
  }
  checkpoint.save(stats);
  costs.append = seconds_since(t0) - costs.fixed;
  costs.record_bytes = static_cast<double>(fs::file_size(dir / "part-0-rank0.records"));
}

CheckpointCosts measure(const char* name, const fs::path& where) {
  const auto [job, spec] = read_ensemble_job(JobDocument::read(std::string(TREEDYN_JOBS_DIR) + "/" + name + ".toml"));
  ensemble::SampleRunner runner(job, spec);
  std::vector<double> nominal, trajectory;
  runner.run(0, true, nominal);
  std::vector<double> sample_times;
  SampleRecord record;
  for (int k = 0; k < 3; ++k) {
    const auto t0 = Clock::now();
    record = runner.run(static_cast<std::uint64_t>(k), false, trajectory);
    sample_times.push_back(seconds_since(t0));
  }
  CheckpointCosts costs;
  costs.sample = median(sample_times);
  const fs::path dir = where / ("treedyn_checkpoint_benchmark_" + std::string(name));
  fs::remove_all(dir);
  fs::create_directories(dir);
  // trajectory: what a sample below store_trajectories carries
  measure_saves(dir, job, spec, filled_statistics(runner, spec, nominal), record, trajectory, costs);
  fs::remove_all(dir);
  return costs;
}

}  // namespace

int main(int argc, char** argv) {
  const fs::path where = argc > 1 ? fs::path(argv[1]) : fs::temp_directory_path();
  const int ranks = argc > 2 ? std::atoi(argv[2]) : 2;
  const char* jobs[] = {"spherical_pendulum", "double_pendulum", "chain10", "y_tree", "crane_payload", "kapitza"};
  std::printf(
      "| job | sample (ms) | statistics per checkpoint (MiB) | one checkpoint (ms) | on a stop signal, "
      "not flushed (ms) | 10,000 records (MiB) | appending them (ms) | overhead at 300 s, %d ranks |\n"
      "|---|---:|---:|---:|---:|---:|---:|---:|\n",
      ranks);
  for (const char* name : jobs) {
    const CheckpointCosts c = measure(name, where);
    const double wall = kSamples * c.sample / ranks;
    const double checkpoints = std::floor(wall / kInterval) + 1.0;
    const double overhead = (checkpoints * c.fixed + c.append / ranks) / wall;
    std::printf("| %s | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.3f %% |\n", name, 1e3 * c.sample,
                c.state_bytes / 1048576.0, 1e3 * c.fixed, 1e3 * c.unflushed, c.record_bytes / 1048576.0, 1e3 * c.append,
                100.0 * overhead);
    std::fflush(stdout);
  }
  return 0;
}
