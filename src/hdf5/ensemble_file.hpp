// The ensemble's HDF5 file, written by one rank: per-sample records as they
// arrive (by sample index, any order), then the nominal run and the
// statistics. Temporary name until finish() renames it into place.
#pragma once

#include <filesystem>
#include <vector>

#include "ensemble/answers.hpp"
#include "ensemble/ensemble_spec.hpp"
#include "ensemble/sample_runner.hpp"
#include "ensemble/statistics.hpp"
#include "hdf5/hdf5.hpp"
#include "hdf5/provenance.hpp"

namespace treedyn {

struct EnsembleSummary {
  std::uint64_t ok = 0, failed = 0;
  int ranks = 1;
  double wall_seconds = 0.0;
  std::vector<double> peak_rss_mib;      // per rank (getrusage maximum resident set)
  std::vector<long long> samples_per_rank;  // samples each rank integrated
  std::vector<double> busy_seconds;      // time each rank spent integrating samples
};

class EnsembleWriter {
 public:
  EnsembleWriter(const std::filesystem::path& path, const Job& job,
                 const ensemble::EnsembleSpec& spec, const ColumnLayout& layout,
                 std::size_t final_state_size);

  void write_records(std::vector<ensemble::SampleRecord> records);
  void write_nominal(const std::vector<double>& trajectory);
  void write_statistics(const ensemble::EnsembleStatistics& stats);
  // /responses/<name> and /sensitivity/<name>, one per spec response.
  void write_answers(const std::vector<ensemble::ResponseAnswer>& answers);
  void finish(const EnsembleSummary& summary, const RunProvenance& run);
  // A merged file: the part files it came from and the sample ranges they
  // held, root attributes merged_from (strings) and held_samples ((K, 2),
  // [first, end) rows). Call before finish().
  void write_merge_origin(const std::vector<std::string>& parts,
                          const std::vector<std::pair<std::uint64_t, std::uint64_t>>& held);

 private:
  void write_run(const std::vector<ensemble::SampleRecord>& run);

  const Job& job_;
  const ensemble::EnsembleSpec& spec_;
  const ColumnLayout& layout_;
  std::size_t final_size_;
  h5::File file_;
  h5::Handle samples_, inputs_, status_, reason_, time_reached_, integrator_stats_, final_state_;
  h5::Handle responses_;
  std::vector<h5::Handle> reduction_groups_;         // /samples/<reduction>
  std::vector<std::vector<h5::Handle>> reductions_;  // [reduction][quantity]
  h5::Handle trajectory_group_;
  std::vector<h5::Handle> trajectories_;             // [quantity], (M, T, columns)
};

}  // namespace treedyn
