// Checkpoints of an ensemble run, so that a killed run resumes where it was
// and the result is bitwise that of an uninterrupted run.
//
// The statistics are exact integer sums (order-independent), so every rank
// checkpoints on its own, with no collective: the union of the ranks'
// checkpoints is consistent whatever moment each was written at and
// whichever rank died. In the directory OUT.h5.checkpoint/:
//
//   common.state           the nominal run and the calibration (rank 0, once
//                          the pilot wave is done)
//   part-G-R.records       rank R's finished records, appended in frames
//   part-G-R.state         rank R's statistics and how many bytes of its
//                          records file they cover (written atomically)
//   base-G.state/.records  everything restored by the resume that started
//                          generation G (G >= 1)
//
// A generation G is complete when G = 0 or base-G.state exists; loading takes
// the newest complete generation, its base and all of its parts. State files
// are written atomically (process/atomic_file.hpp) in the envelope of
// persistence/state_file.hpp; a records file is append-only and its tail
// beyond what a state covers is ignored, so kill -9 at any moment leaves a
// loadable directory. Which waves are done is not stored: the design's plan
// replays its decisions from the restored records.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "output/sample_record.hpp"
#include "persistence/state_file.hpp"
#include "statistics/ensemble_statistics.hpp"
#include "statistics/tolerance_check.hpp"

namespace treedyn::persistence {

std::filesystem::path checkpoint_directory(const std::filesystem::path& output);

// Rank 0, once the calibration is known. Throws process::FileError.
void write_checkpoint_common(const std::filesystem::path& dir, const RunIdentity& id,
                             const std::vector<double>& nominal, const statistics::Calibration& calibration,
                             const statistics::ToleranceCheck& tolerance);

// One rank's checkpoint in generation `generation`: records are added as
// they finish; save() appends them to the records file and rewrites the
// state with the rank's statistics (which must count exactly the ok records
// added so far). Not thread-safe: its owner serialises add() and save().
class RankCheckpoint {
 public:
  RankCheckpoint(std::filesystem::path dir, RunIdentity id, std::uint64_t generation, const std::string& name);
  // Once the records held pass kSpillBytes they are appended to the records
  // file as a frame (no fsync), so a rank's memory does not grow with the
  // samples it runs between two saves; a frame past the saved state's end
  // is ignored by load_checkpoint until a save covers it. The caller holds
  // its lock through the write (RankResults: a signal's save waits for it,
  // a few ms on a local disk). Throws process::FileError (the run goes on
  // without checkpoints), and so does every later add or save.
  void add(const SampleRecord& record);
  static constexpr std::size_t kSpillBytes = std::size_t{4} << 20;
  // Throws process::FileError (the run goes on without checkpoints).
  void save(const statistics::EnsembleStatistics& stats,
            process::AtomicFile::Sync sync = process::AtomicFile::Sync::yes);
  // A flushed save in two steps, the second free to run on another thread
  // while `stats` change (RankResults::finish): prepare_save() appends the
  // records and writes the state into its temporary, without a flush;
  // commit_prepared() flushes the records, then the state, renames it into
  // place and flushes the directory; save() is the two at once. A prepared
  // save not committed leaves the state before it (the records it appended
  // lie past that state's end, ignored). Both throw process::FileError; no
  // other save may come between the two (std::logic_error): they would
  // share the temporary's name.
  void prepare_save(const statistics::EnsembleStatistics& stats);
  void commit_prepared();
  std::uint64_t saved_records() const { return saved_records_; }
  bool has_unsaved() const { return pending_records_ > 0 || appended_records_ > saved_records_; }
  std::size_t held_bytes() const { return pending_.size(); }

 private:
  void append_pending();  // unflushed: a flushed save flushes the records file
  void commit(process::AtomicFile::Sync sync);
  void flush_saved();
  void refuse_after_failure() const;
  void refuse_while_prepared() const;
  std::filesystem::path records_file() const;
  std::filesystem::path state_file() const;

  std::filesystem::path dir_;
  RunIdentity id_;
  std::uint64_t generation_;
  std::string name_;
  std::vector<char> pending_;  // one frame: the encoded records not yet in the records file
  std::uint64_t pending_records_ = 0;
  std::uint64_t appended_records_ = 0, appended_bytes_ = 0;  // in the records file
  std::uint64_t saved_records_ = 0;                          // of those, covered by the state file
  std::uint64_t flushed_records_ = 0;                        // of those, known to be on the disk (fsync)
  bool saved_once_ = false;
  bool saved_flushed_ = false;                 // the last save reached the disk (Sync::yes)
  bool failed_ = false;                        // an append failed: no further write
  std::unique_ptr<StateFileWriter> prepared_;  // prepare_save()'s state, in its temporary
  std::uint64_t prepared_records_ = 0;         // the records it covers
};

// What every record of a job must look like: loading refuses any other (a
// damaged or forged file must not reach the writers).
struct RecordShape {
  std::uint64_t first = 0, end = 0;  // the sample indices
  std::size_t inputs = 0, reductions = 0, responses = 0, final_state = 0;
  std::size_t trajectory = 0;  // entries, for samples < stored
  std::uint64_t stored = 0;    // store_trajectories
  // Records from this index on are not in the statistics (a subset
  // simulation's levels after 0); by default every record is.
  std::uint64_t statistics_end = UINT64_MAX;
};
// Throws CheckpointError naming `what` for the first record that does not fit.
void check_records(const std::vector<SampleRecord>& records, const RecordShape& shape, const std::string& what);

// The statistics' shape: times x columns entries, bins.
struct StatisticsShape {
  std::size_t times = 0, columns = 0;
  int bins = 0;
};

// What a checkpoint directory holds, summed over the ranks.
struct RestoredRun {
  std::uint64_t generation = 0;  // the one loaded
  std::vector<double> nominal;
  statistics::Calibration calibration;
  statistics::ToleranceCheck tolerance;                           // the pilot's (statistics/tolerance_check.hpp)
  std::vector<SampleRecord> records;                              // sorted by sample index
  std::vector<std::pair<std::uint64_t, std::uint64_t>> finished;  // [first, end) intervals
  std::optional<statistics::EnsembleStatistics> statistics;       // counts exactly the ok records
};

// nullopt when there is no checkpoint (or no common.state yet: the run was
// killed before its pilot wave was done). Throws CheckpointError for another
// job or build (the message says which) or a damaged file.
std::optional<RestoredRun> load_checkpoint(const std::filesystem::path& dir, const RunIdentity& id,
                                           const StatisticsShape& stats, const RecordShape& records);

// Rank 0 at the start of a resumed run: everything restored becomes
// base-(G+1), written atomically; then the older generations are deleted.
// Returns G + 1, the generation the resumed run's parts belong to. Throws
// process::FileError.
std::uint64_t consolidate_checkpoint(const std::filesystem::path& dir, const RunIdentity& id,
                                     const RestoredRun& restored);

// Whether the directory holds a checkpoint (common.state): a fresh run
// refuses to overwrite one.
bool checkpoint_exists(const std::filesystem::path& dir);
// Whether a resume would restore samples from it: common.state and at least
// one rank's state of the newest generation. A failed run removes a
// checkpoint that holds none (only the nominal run, or records whose rank
// state could not be saved).
bool checkpoint_holds_samples(const std::filesystem::path& dir);

// An empty checkpoint directory, and its name in its parent flushed to the
// disk (the files' saves flush only the directory itself). Throws
// process::FileError.
void create_checkpoint_directory(const std::filesystem::path& dir);

// Removes the whole directory: renamed away first, so that a kill in the
// middle leaves no half-deleted checkpoint.
void remove_checkpoint(const std::filesystem::path& dir);

}  // namespace treedyn::persistence
