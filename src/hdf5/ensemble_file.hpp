// The ensemble's HDF5 file, written by one rank: per-sample records as they
// arrive (by sample index, any order), then the nominal run, the
// statistics (statistics_file.hpp) and the answers (answers_file.hpp).
// Temporary name until complete() renames it into place.
#pragma once

#include <chrono>
#include <filesystem>
#include <vector>

#include "analysis/answers.hpp"
#include "designs/design_answer.hpp"
#include "ensemble/run_summary.hpp"
#include "ensemble/sample_rows.hpp"
#include "hdf5/hdf5.hpp"
#include "hdf5/provenance.hpp"
#include "hdf5/row_dataset.hpp"
#include "hdf5/unit_chunks.hpp"
#include "job/ensemble_spec.hpp"
#include "output/quantities.hpp"
#include "output/sample_record.hpp"
#include "statistics/ensemble_statistics.hpp"

namespace treedyn::h5 {

class EnsembleWriter {
 public:
  // `unit_rows` > 0: every per-sample dataset of numbers, and the reasons,
  // in chunks of that many rows, so that a unit of as many samples is one
  // chunk of each (write_unit); 0: chunks of about 64 KiB each.
  EnsembleWriter(const std::filesystem::path& path, const Job& job, const EnsembleSpec& spec,
                 const ColumnLayout& layout, std::size_t final_state_size, std::size_t unit_rows = 0);
  EnsembleWriter(const EnsembleWriter&) = delete;  // sample_sets_ points into it
  EnsembleWriter& operator=(const EnsembleWriter&) = delete;

  // Per-sample records, as they arrive (any order, any batches).
  void write_records(std::vector<SampleRecord> records);
  // The layout of the per-sample rows, for a sender's UnitEncoder.
  const ensemble::SampleRows& sample_rows() const { return rows_; }
  // A unit's whole chunks (unit_chunks.hpp), stored as they are, and its
  // records' reasons. Its records (stripped) are the caller's to count.
  void write_unit(const Unit& unit);
  // A merged file: the part files it came from and the sample ranges they
  // held, root attributes merged_from (strings) and held_samples ((K, 2),
  // [first, end) rows). Call before complete().
  void write_merge_origin(const std::vector<std::string>& parts,
                          const std::vector<std::pair<std::uint64_t, std::uint64_t>>& held);
  // Keeps the rows of samples 0 .. rows-1 only (a run a stopping rule or
  // subset simulation's last level ended early); before complete().
  void keep_samples(std::size_t rows);
  // The design's answer for the whole run (designs/design_answer.hpp:
  // subset simulation's /rare_event and /samples/level, chain, state), rows
  // 0 .. rows-1 kept; before complete().
  void write_run_answer(const designs::RunAnswer& answer, std::size_t rows);
  // The end of every ensemble file, whoever wrote its records (a run, a
  // merge): the per-sample datasets' last chunks, the nominal run, /stats,
  // /responses and /sensitivity (one per response; none when `answers` is
  // empty), the summary and provenance as root attributes; then the file is
  // flushed and renamed into place. Returns the summary as written: its
  // wall time from `started` to the attributes, the last chunks' time added
  // to the first rank's record writing.
  ensemble::RunSummary complete(const std::vector<double>& nominal, const statistics::EnsembleStatistics& stats,
                                const std::vector<analysis::ResponseAnswer>& answers,
                                const statistics::ToleranceCheck& tolerance, ensemble::RunSummary summary,
                                const RunProvenance& run, std::chrono::steady_clock::time_point started);

 private:
  void create_sample_columns();
  void create_reductions();
  void create_trajectories();
  void write_run(const std::vector<SampleRecord>& run);
  void write_trajectories(const std::vector<SampleRecord>& run);
  void write_reasons(std::span<const SampleRecord> records, std::size_t first);
  RowDataset& sample_set(const ensemble::SampleRows::Dataset& d);
  // Every per-sample dataset of numbers (hdf5/row_dataset.hpp).
  std::vector<RowDataset*> row_datasets();
  void write_nominal(const std::vector<double>& trajectory);
  void finish(const ensemble::RunSummary& summary, const RunProvenance& run);

  const Job& job_;
  const EnsembleSpec& spec_;
  const ColumnLayout& layout_;
  std::size_t final_size_, unit_rows_;
  ensemble::SampleRows rows_;
  File file_;
  Handle samples_, reason_;
  std::vector<hsize_t> reason_rows_;  // write_reasons' rows and texts, reused
  std::vector<const char*> reason_texts_;
  RowDataset inputs_, status_, time_reached_, integrator_stats_, final_state_, responses_;
  std::vector<Handle> reduction_groups_;             // /samples/<reduction>
  std::vector<std::vector<RowDataset>> reductions_;  // [reduction][quantity]
  Handle trajectory_group_;
  std::vector<RowDataset> trajectories_;  // [quantity], (M, T, columns)
  std::vector<RowDataset*> sample_sets_;  // rows_'s datasets, in its order
};

}  // namespace treedyn::h5
