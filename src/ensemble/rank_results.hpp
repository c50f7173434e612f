// What this rank has finished, and its checkpoint. Two threads change them:
// the main thread keeps each finished sample and saves now and then; the
// signal thread (process/signals.hpp) saves at once when a stop signal
// comes, so that whatever is finished is on disk before a launcher's
// SIGKILL, even while the main thread is blocked in MPI waiting for a rank
// that died. One lock guards both.
#pragma once

#include <chrono>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <thread>

#include "output/sample_record.hpp"
#include "persistence/checkpoint.hpp"
#include "statistics/ensemble_statistics.hpp"

namespace treedyn::ensemble {

class RankResults {
 public:
  // Checkpoints into `checkpoint` every `every` seconds (none: no checkpoints).
  void use_checkpoint(std::unique_ptr<persistence::RankCheckpoint> checkpoint, double every_seconds);
  // The statistics, from the end of the pilot wave on (the pilot's own
  // samples already added), or restored.
  void start_statistics(statistics::EnsembleStatistics stats);
  bool has_statistics() const { return stats_.has_value(); }

  // A finished sample: its record into the checkpoint and, when it succeeded
  // and the statistics exist, its trajectory into them, without a copy
  // (EnsembleStatistics::take_sample: `trajectory` gets storage of the same
  // size back). No trajectory (nullptr, or empty) stays out: a subset
  // simulation's chain runs are not a Monte-Carlo sample. False once
  // stopped: the sample is not kept (a resumed run runs it again).
  bool keep(const SampleRecord& record, std::vector<double>* trajectory);

  // Main thread: saves when the interval has passed (flushed to the disk).
  void save_if_due();
  // Saves now. False when there is nothing to save to, or the save failed.
  bool save(process::AtomicFile::Sync sync = process::AtomicFile::Sync::yes);
  // Signal thread (the stop's action): no sample is kept after this; what
  // is kept is saved at once (not flushed: the deadline is SIGKILL's).
  void stop();

  bool checkpointing() const;
  std::uint64_t saved_records() const;
  // Checkpoints off from now on (a failed write, or common.state missing).
  void drop_checkpoint();
  // The statistics, read by the main thread between waves (the calibration).
  const statistics::EnsembleStatistics& statistics() const { return *stats_; }

  // After the last wave: saves what is not saved yet (flushed, so a failed
  // final write leaves everything for --resume), hands the statistics over
  // for the reduction, and ends the signal thread's part: keep(), save()
  // and stop() do nothing from now on. The save is written here; its
  // flush and rename run on a thread of their own, overlapping the
  // reduction and the output's writing. Flushed although a run that ends
  // well removes it: unflushed, a crash of the machine after its rename
  // could leave a state naming records the disk never got, and --resume
  // would refuse the whole checkpoint.
  statistics::EnsembleStatistics finish();
  // Waits until finish()'s save is on the disk (a failure turns this rank's
  // checkpoints off, and its warning is printed here, on the main thread,
  // not in the middle of rank 0's summary): before the checkpoint is
  // removed or judged, and before the process ends. Main thread only.
  void await_final_save();
  ~RankResults();

 private:
  bool save_locked(process::AtomicFile::Sync sync);
  // A failed write (a full disk, or no memory for the buffers) turns
  // checkpoints off on this rank; returns the warning, printed once by the
  // caller. Under the lock.
  std::string drop_checkpoint_after(const std::exception& failure);
  // finish()'s save committed (flushed, renamed); a failure's warning is
  // kept for await_final_save(). Under the lock.
  void commit_final_save();

  mutable std::mutex lock_;
  std::optional<statistics::EnsembleStatistics> stats_;
  std::unique_ptr<persistence::RankCheckpoint> checkpoint_;
  double every_ = 0.0;
  std::chrono::steady_clock::time_point last_save_ = std::chrono::steady_clock::now();
  bool stopped_ = false;
  bool finished_ = false;
  std::thread final_save_;          // finish()'s flush and rename
  std::string final_save_warning_;  // its failure, printed by await_final_save()
};

}  // namespace treedyn::ensemble
