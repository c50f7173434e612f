#include "ensemble/rank_results.hpp"

#include <iostream>

namespace treedyn::ensemble {

void RankResults::use_checkpoint(std::unique_ptr<persistence::RankCheckpoint> checkpoint, double every_seconds) {
  std::lock_guard<std::mutex> guard(lock_);
  checkpoint_ = std::move(checkpoint);
  every_ = every_seconds;
}

void RankResults::start_statistics(statistics::EnsembleStatistics stats) {
  std::lock_guard<std::mutex> guard(lock_);
  stats_.emplace(std::move(stats));
}

bool RankResults::keep(const SampleRecord& record, std::vector<double>* trajectory) {
  std::lock_guard<std::mutex> guard(lock_);
  if (stopped_ || finished_) return false;
  if (stats_ && record.status == SampleStatus::ok && trajectory != nullptr && !trajectory->empty())
    stats_->take_sample(*trajectory);
  if (checkpoint_) {
    try {
      checkpoint_->add(record);
    } catch (const process::FileError& e) {  // a spill of the held records failed
      std::cerr << drop_checkpoint_after(e);
    }
  }
  return true;
}

void RankResults::save_if_due() {
  std::lock_guard<std::mutex> guard(lock_);
  const double since = std::chrono::duration<double>(std::chrono::steady_clock::now() - last_save_).count();
  if (checkpoint_ && since >= every_) save_locked(process::AtomicFile::Sync::yes);
}

bool RankResults::save(process::AtomicFile::Sync sync) {
  std::lock_guard<std::mutex> guard(lock_);
  return save_locked(sync);
}

void RankResults::stop() {
  std::lock_guard<std::mutex> guard(lock_);
  stopped_ = true;
  save_locked(process::AtomicFile::Sync::no);
}

bool RankResults::save_locked(process::AtomicFile::Sync sync) {
  if (!checkpoint_ || !stats_ || finished_) return false;
  try {
    checkpoint_->save(*stats_, sync);
    last_save_ = std::chrono::steady_clock::now();
    return true;
  } catch (const std::exception& e) {
    std::cerr << drop_checkpoint_after(e);
    return false;
  }
}

std::string RankResults::drop_checkpoint_after(const std::exception& failure) {
  checkpoint_.reset();
  return std::string("warning: ") + failure.what() + "; checkpoints are off for this rank\n";
}

statistics::EnsembleStatistics RankResults::finish() {
  std::lock_guard<std::mutex> guard(lock_);
  if (checkpoint_ && stats_ && !finished_) {
    try {
      checkpoint_->prepare_save(*stats_);
      try {
        final_save_ = std::thread([this] {
          std::lock_guard<std::mutex> committing(lock_);  // taken once finish() returns
          commit_final_save();
        });
      } catch (const std::exception&) {  // no thread to be had (system_error, bad_alloc): here and now
        commit_final_save();
      }
    } catch (const std::exception& e) {
      std::cerr << drop_checkpoint_after(e);
    }
  }
  finished_ = true;
  statistics::EnsembleStatistics out = std::move(*stats_);
  stats_.reset();
  return out;
}

// Under the lock.
void RankResults::commit_final_save() {
  if (!checkpoint_) return;
  try {
    checkpoint_->commit_prepared();
    last_save_ = std::chrono::steady_clock::now();
  } catch (const std::exception& e) {
    final_save_warning_ = drop_checkpoint_after(e);
  }
}

void RankResults::await_final_save() {
  if (final_save_.joinable()) final_save_.join();
  std::lock_guard<std::mutex> guard(lock_);
  std::cerr << final_save_warning_;
  final_save_warning_.clear();
}

RankResults::~RankResults() { await_final_save(); }

bool RankResults::checkpointing() const {
  std::lock_guard<std::mutex> guard(lock_);
  return checkpoint_ != nullptr;
}

std::uint64_t RankResults::saved_records() const {
  std::lock_guard<std::mutex> guard(lock_);
  return checkpoint_ ? checkpoint_->saved_records() : 0;
}

void RankResults::drop_checkpoint() {
  std::lock_guard<std::mutex> guard(lock_);
  checkpoint_.reset();
}

}  // namespace treedyn::ensemble
