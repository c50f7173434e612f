// Checkpoints of an ensemble run, so that a killed run resumes where it was
// and the result is bitwise that of an uninterrupted run.
//
// The statistics are exact integer sums (order-independent), so every rank
// can checkpoint on its own, with no collective: the union of the ranks'
// checkpoints is always consistent, whatever moment each was written at and
// whichever rank died. In the directory OUT.h5.checkpoint/:
//
//   common.state           identity, nominal run, calibration (rank 0, once,
//                          after the pilot samples)
//   part-G-R.records       rank R's finished records, appended in frames
//   part-G-R.state         rank R's statistics and how many bytes of its
//                          records file they cover (written atomically)
//   base-G.state/.records  everything restored by the resume that started
//                          generation G (G >= 1)
//
// A generation G is complete when G = 0 or base-G.state exists; loading takes
// the newest complete generation, its base and all of its parts. A state file
// is written to a temporary name, flushed to disk and renamed; a records file
// is append-only and its tail beyond what a state file covers is ignored, so
// kill -9 at any moment leaves a loadable directory. Every file starts with
// the identity (job text hash, treedyn version and build) and ends with a
// checksum.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "ensemble/sample_runner.hpp"
#include "ensemble/statistics.hpp"

namespace treedyn::ensemble {

// A checkpoint that cannot be used: another job or build, or a damaged file.
class CheckpointError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Who may resume whom: the job text and the build.
struct CheckpointIdentity {
  std::string job_hash;  // FNV-1a 64 of the job file's bytes, hex
  std::string build;     // treedyn version, git commit, build type, compiler
};
CheckpointIdentity checkpoint_identity(const std::string& job_text, const std::string& build);

std::filesystem::path checkpoint_directory(const std::filesystem::path& output);

// Rank 0, once the calibration is known. Creates the directory if needed.
void write_checkpoint_common(const std::filesystem::path& dir, const CheckpointIdentity& id,
                             const std::vector<double>& nominal, const Calibration& calibration);

// One rank's checkpoint in generation `generation`: records are added as
// they finish; save() appends them to the records file and rewrites the
// state with the rank's statistics (which must count exactly the ok records
// added so far).
class RankCheckpoint {
 public:
  RankCheckpoint(std::filesystem::path dir, CheckpointIdentity id, std::uint64_t generation,
                 const std::string& name);
  void add(const SampleRecord& record);
  // Throws CheckpointError on an I/O failure (the run goes on without it).
  void save(EnsembleStatistics& stats);
  std::uint64_t saved_records() const { return saved_records_; }

 private:
  std::filesystem::path dir_;
  CheckpointIdentity id_;
  std::uint64_t generation_;
  std::string name_;
  std::vector<char> pending_;  // encoded records not yet in the records file
  std::uint64_t pending_records_ = 0, saved_records_ = 0, saved_bytes_ = 0;
};

// What every record of a job must look like: loading refuses any other (a
// damaged or forged file must not reach the writers).
struct RecordShape {
  std::uint64_t first = 0, end = 0;  // the sample indices
  std::size_t inputs = 0, reductions = 0, responses = 0, final_state = 0;
  std::size_t trajectory = 0;        // entries, for samples < stored
  std::uint64_t stored = 0;          // store_trajectories
};
// Throws CheckpointError naming `what` for the first record that does not fit.
void check_records(const std::vector<SampleRecord>& records, const RecordShape& shape, const std::string& what);
// Finite values, positive scales and widths, of `entries` each.
void check_calibration(const Calibration& c, std::size_t entries, const std::string& what);

// What a checkpoint directory holds, summed over the ranks.
struct RestoredRun {
  std::uint64_t generation = 0;  // the one loaded
  std::vector<double> nominal;
  Calibration calibration;
  std::vector<SampleRecord> records;                 // sorted by sample index
  std::vector<std::pair<std::uint64_t, std::uint64_t>> finished;  // [first, end) intervals
  std::vector<char> statistics;                      // summed raw statistics (restore_statistics)
  std::uint64_t ok_samples = 0;
};

// nullopt when there is no checkpoint (or no common.state yet: the run was
// killed before its pilot samples were done). Throws CheckpointError for
// another job or build (the message says which) or a damaged file.
std::optional<RestoredRun> load_checkpoint(const std::filesystem::path& dir, const CheckpointIdentity& id,
                                           std::size_t entries, int bins, const RecordShape& shape);

// Adds restored raw statistics into `stats` (same shape and calibration).
void restore_statistics(const std::vector<char>& raw, EnsembleStatistics& stats);

// Rank 0 at the start of a resumed run: everything restored (the records,
// and `restored_stats`, which counts exactly them) becomes base-(G+1),
// written atomically; then the older generations are deleted. Returns G + 1,
// the generation the resumed run's parts belong to.
std::uint64_t consolidate_checkpoint(const std::filesystem::path& dir, const CheckpointIdentity& id,
                                     const RestoredRun& restored, EnsembleStatistics& restored_stats);

// Removes the whole directory (after a complete run): renamed away first, so
// that a kill in the middle leaves no half-deleted checkpoint.
void remove_checkpoint(const std::filesystem::path& dir);

// A part of a split ensemble (--samples FIRST:END): everything the merge
// needs, in one file written atomically, with the identity of the job and
// build (the job text itself too, so that the merge needs no job file).
struct PartFile {
  CheckpointIdentity id;
  std::string job_text, job_path;
  std::uint64_t first = 0, end = 0;  // the sample indices it covers, [first, end)
  std::vector<double> nominal;
  Calibration calibration;
  int bins = 0;                      // read_part_file only
  std::vector<char> statistics;      // raw, read_part_file only (restore_statistics)
  std::vector<SampleRecord> records; // every sample of the range
};
// Writes `part` with the statistics of `stats`. Throws CheckpointError.
void write_part_file(const std::filesystem::path& path, const PartFile& part, EnsembleStatistics& stats);
// Throws CheckpointError for a file that is not a part or is damaged.
PartFile read_part_file(const std::filesystem::path& path);

// Temporary files `<name>.tmp-PID` in `dir` whose process no longer runs
// (kill -9, a node that died): removed, and their names returned. Only PIDs
// of this host can be checked, so a file whose process lives is kept.
std::vector<std::string> remove_stale_temporaries(const std::filesystem::path& dir, const std::string& name);

}  // namespace treedyn::ensemble
