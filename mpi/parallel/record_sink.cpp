#include "parallel/record_sink.hpp"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "persistence/record_codec.hpp"

namespace treedyn::parallel {
namespace {

constexpr int kTagRecords = 1;
constexpr int kTagDone = 2;
constexpr int kTagUnit = 3;
// Batches in flight per rank. A batch above MPI's eager limit is sent only
// once rank 0 receives it, and rank 0 does not receive while it writes a
// batch of records: the other ranks go on integrating as long as they may
// keep this much in flight.
constexpr std::size_t kMaxPendingSends = 64;
constexpr std::size_t kMaxPendingBytes = std::size_t{8} << 20;
constexpr std::int64_t kPollIntervalNs = 2'000'000;
constexpr std::size_t kWriteBatchBytes = std::size_t{4} << 20;  // rank 0's records held before a write
constexpr std::size_t kWriteBatchRecords = 4096;
// A sending rank holds the records of its blocks until they make a message
// of kSendBytes, or the first has waited kMaxHoldSeconds: rank 0 pays a
// fixed cost per message it receives, whatever its size (the probe, MPI's
// rendezvous above the eager limit, the decode's set-up; BENCHMARKS.md,
// "One message per 64 KiB of records"). The records all senders hold
// together stay under kAllHeldBytes: held records are rows rank 0 has not
// got, and it keeps only a few chunks waiting for their rows
// (h5::RowDataset), so with many ranks a message is smaller.
constexpr std::size_t kSendBytes = std::size_t{64} << 10;
constexpr std::size_t kAllHeldBytes = std::size_t{512} << 10;
constexpr double kMaxHoldSeconds = 0.5;
// Rank 0 takes in new messages only while those it is receiving come to
// less than kMostReceivingBytes (one largest unit's), into buffers it keeps
// for the next ones, up to kSpareBytes together. Units of many senders come in a
// burst: receiving all at once would cost rank 0 memory without bound and
// a fresh buffer each (its page faults and unmapping).
constexpr std::size_t kMostReceivingBytes = std::size_t{32} << 20;
constexpr std::size_t kSpareBytes = kMostReceivingBytes;

// A sender's message size when `ranks` ranks run: kSendBytes, less beyond
// 9 ranks so that the ranks - 1 senders hold kAllHeldBytes together.
std::size_t message_bytes(int ranks) {
  return std::min(kSendBytes, kAllHeldBytes / static_cast<std::size_t>(std::max(ranks - 1, 1)));
}

// What a record holds in memory, roughly: its numbers and its reason.
std::size_t record_bytes(const SampleRecord& r) {
  const std::size_t numbers =
      r.inputs.size() + r.reductions.size() + r.responses.size() + r.final_state.size() + r.trajectory.size();
  return sizeof r + r.reason.size() + numbers * sizeof(double);
}

}  // namespace

// The coarse clock (a value the kernel updates every tick, read without the
// time-stamp counter), since poll() runs at every output time and the
// precise clock there is a visible share of a small model's sample
// (BENCHMARKS.md, "Longer runs"). So MPI progresses once a tick rather than
// every kPollIntervalNs, which the sends in flight absorb. Linux-only, as
// the project is.
void RecordSink::poll() {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC_COARSE, &now);
  const std::int64_t ns = std::int64_t{now.tv_sec} * 1'000'000'000 + now.tv_nsec;
  if (ns - last_poll_ns_ < kPollIntervalNs) return;
  last_poll_ns_ = ns;
  make_progress();
}

// The clock run_sample times samples with, so that the writing inside a
// sample can be taken out of it.
RecordSink::Writing::Writing(RecordSink& sink) : sink_(sink) {
  if (sink_.writing_depth_++ != 0) return;
  start_ = std::chrono::steady_clock::now();
  start_cpu_ = thread_cpu_seconds();
}

RecordSink::Writing::~Writing() {
  if (--sink_.writing_depth_ != 0) return;
  sink_.writing_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  sink_.writing_cpu_seconds_ += thread_cpu_seconds() - start_cpu_;
}

RecordWriter::RecordWriter(MPI_Comm comm, int ranks, h5::EnsembleWriter* writer, ensemble::Progress& progress,
                           ensemble::ResponseTable* table, std::vector<SampleRecord>* collected)
    : comm_(comm),
      ranks_(ranks),
      writer_(writer),
      progress_(progress),
      table_(table),
      collected_(collected),
      spare_(kSpareBytes) {}

void RecordWriter::add(SampleRecord record) { local_.push_back(std::move(record)); }

void RecordWriter::end_block() {
  if (!local_.empty()) {
    const Writing writing(*this);
    write(std::move(local_));
  }
  local_.clear();
  drain(false);
}

// Every record of the wave has arrived (counted, in the table) when this
// returns; those held stay held: a stopped run would only write them into
// the output it is about to delete, inside the launcher's SIGTERM-to-SIGKILL
// window. finish_run writes them (write_held) once the run is complete.
void RecordWriter::end_wave() {
  end_block();
  // Every rank's done message comes after its records (MPI does not let a
  // sender's messages overtake each other in matching), but a posted
  // receive of records may complete after it: wait for those too.
  while (finished_ranks_ < ranks_ - 1 || !receiving_.empty()) drain(true);
  finished_ranks_ = 0;
}

void RecordWriter::count(const SampleRecord& r) {
  ++done_;
  if (r.status != SampleStatus::ok) ++failed_;
  if (table_) table_->add(r);
}

void RecordWriter::write(std::vector<SampleRecord> records) {
  for (auto& r : records) {
    count(r);
    if (!io_error_.empty()) continue;  // nothing more goes to a file that failed
    batch_bytes_ += record_bytes(r);
    batch_.push_back(std::move(r));
  }
  if (batch_bytes_ >= kWriteBatchBytes || batch_.size() >= kWriteBatchRecords) write_held();
  progress_.update(done_, failed_);
}

void RecordWriter::write_held() {
  if (batch_.empty()) return;
  const Writing writing(*this);
  try {
    if (collected_)
      for (auto& r : batch_) collected_->push_back(std::move(r));
    else
      writer_->write_records(std::move(batch_));
  } catch (const std::exception& e) {
    io_error_ = e.what();  // keep receiving: the other ranks must not block
  }
  batch_.clear();
  batch_bytes_ = 0;
}

// Receives what has arrived: every message matched is posted (MPI_Imrecv),
// every posted one that has completed is written. With `wait`, blocks
// until at least one message has completed.
void RecordWriter::drain(bool wait) {
  post_arrived();
  bool progressed = complete_received(false);
  while (wait && !progressed) {
    if (receiving_.empty()) {  // nothing posted: wait for a message to match
      MPI_Message message;
      MPI_Status status;
      MPI_Mprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, comm_, &message, &status);
      post(message, status);
    }
    progressed = complete_received(true);
  }
}

// Every message that has arrived, matched and posted, while those posted
// hold less than kMostReceivingBytes; the others wait in MPI's queue.
void RecordWriter::post_arrived() {
  while (receiving_bytes_ < kMostReceivingBytes) {
    int flag = 0;
    MPI_Message message;
    MPI_Status status;
    MPI_Improbe(MPI_ANY_SOURCE, MPI_ANY_TAG, comm_, &flag, &message, &status);
    if (!flag) return;
    post(message, status);
  }
}

// A matched message's receive, into a spare buffer.
void RecordWriter::post(MPI_Message& message, const MPI_Status& status) {
  const Writing writing(*this);
  int count = 0;
  MPI_Get_count(&status, MPI_BYTE, &count);
  Receiving r{spare_.take(static_cast<std::size_t>(count)), count, status.MPI_SOURCE, status.MPI_TAG};
  receiving_bytes_ += static_cast<std::size_t>(count);
  requests_.emplace_back();
  MPI_Imrecv(r.bytes.data.get(), count, MPI_BYTE, &message, &requests_.back());
  receiving_.push_back(std::move(r));
}

// The posted messages that have completed, handled; with `wait`, waits for
// one first (the waiting is not writing). Whether any completed.
bool RecordWriter::complete_received(bool wait) {
  if (receiving_.empty()) return false;
  if (wait) {
    int index = MPI_UNDEFINED;
    MPI_Waitany(static_cast<int>(requests_.size()), requests_.data(), &index, MPI_STATUS_IGNORE);
    requests_[static_cast<std::size_t>(index)] = MPI_REQUEST_NULL;  // done: the sweep below takes it
  }
  const Writing writing(*this);
  bool any = false;
  for (std::size_t k = 0; k < receiving_.size();) {
    int done = requests_[k] == MPI_REQUEST_NULL ? 1 : 0;
    if (!done) MPI_Test(&requests_[k], &done, MPI_STATUS_IGNORE);
    if (!done) {
      ++k;
      continue;
    }
    Receiving r = std::move(receiving_[k]);
    receiving_.erase(receiving_.begin() + static_cast<std::ptrdiff_t>(k));
    requests_.erase(requests_.begin() + static_cast<std::ptrdiff_t>(k));
    receiving_bytes_ -= static_cast<std::size_t>(r.count);
    handle(std::span<const char>(r.bytes.data.get(), static_cast<std::size_t>(r.count)), r.source, r.tag);
    spare_.give_back(std::move(r.bytes));
    any = true;
  }
  return any;
}

void RecordWriter::handle(std::span<const char> message, int source, int tag) {
  if (tag == kTagDone)
    ++finished_ranks_;
  else if (tag == kTagUnit)
    write_unit(message, source);
  else
    write(persistence::read_records(message, "the records of rank " + std::to_string(source)));
}

// A unit's chunks go to the file at once (each is whole; nothing to wait
// for), its records are counted.
void RecordWriter::write_unit(std::span<const char> message, int source) {
  if (!writer_) throw std::logic_error("a unit sent to a part's writer (parts have no units)");
  const double start = thread_cpu_seconds();
  h5::decode_unit_into(message, writer_->sample_rows().datasets().size(), "a unit of rank " + std::to_string(source),
                       unit_);
  if (io_error_.empty()) try {
      writer_->write_unit(unit_);
    } catch (const std::exception& e) {
      io_error_ = e.what();
    }
  for (const SampleRecord& r : unit_.records) count(r);
  done_in_units_ += unit_.records.size();
  unit_storing_cpu_seconds_ += thread_cpu_seconds() - start;
  progress_.update(done_, failed_);
}

RecordSender::RecordSender(MPI_Comm comm, int ranks, std::optional<ensemble::SampleRows> rows)
    : comm_(comm), send_bytes_(message_bytes(ranks)), rows_(std::move(rows)) {
  if (rows_) encoder_.emplace(*rows_);
}

void RecordSender::add(SampleRecord record) {
  if (in_unit_) {
    unit_.push_back(std::move(record));
    return;
  }
  if (batch_.empty()) held_since_ = std::chrono::steady_clock::now();
  persistence::append_record(record, batch_);
}

void RecordSender::begin_unit(std::uint64_t first, std::uint64_t rows) {
  in_unit_ = encoder_.has_value();
  unit_first_ = first;
  unit_rows_ = rows;
  unit_.clear();
}

void RecordSender::end_unit(bool stopped) {
  if (!in_unit_) return;
  in_unit_ = false;
  bool whole = unit_.size() == unit_rows_;
  for (std::size_t k = 0; whole && k < unit_.size(); ++k) whole = unit_[k].index == unit_first_ + k;
  if (!whole && stopped) {
    unit_.clear();
    return;
  }
  if (!whole) {
    for (SampleRecord& r : unit_) add(std::move(r));
    unit_.clear();
    return;
  }
  std::vector<char> message;
  encoder_->encode(unit_, message);
  unit_.clear();
  send(std::move(message), kTagUnit);
}

// The records held go when they fill a message, or have waited long enough
// that rank 0's progress would lag (checked here and, within a block of
// slow samples, in make_progress).
void RecordSender::end_block() {
  if (batch_.size() >= send_bytes_ || held_too_long()) send_held();
}

bool RecordSender::held_too_long() const {
  return !batch_.empty() &&
         std::chrono::duration<double>(std::chrono::steady_clock::now() - held_since_).count() >= kMaxHoldSeconds;
}

bool RecordSender::room_in_flight() const {
  return pending_.size() < kMaxPendingSends && pending_bytes_ + batch_.size() <= kMaxPendingBytes;
}

void RecordSender::send_held() {
  if (batch_.empty()) return;
  send(std::move(batch_), kTagRecords);
  batch_.clear();
  batch_.reserve(send_bytes_ + send_bytes_ / 4);  // the next message's, without regrowing from nothing
}

// Waits for room in flight first (a unit may be larger than all of it: it
// then goes alone).
void RecordSender::send(std::vector<char> message, int tag) {
  while (!pending_.empty() &&
         (pending_.size() >= kMaxPendingSends || pending_bytes_ + message.size() > kMaxPendingBytes)) {
    MPI_Wait(&pending_.front().first, MPI_STATUS_IGNORE);
    retire_oldest_send();
  }
  pending_bytes_ += message.size();
  pending_.emplace_back(MPI_REQUEST_NULL, std::move(message));
  auto& [request, buffer] = pending_.back();
  MPI_Isend(buffer.data(), static_cast<int>(buffer.size()), MPI_BYTE, 0, tag, comm_, &request);
}

// The oldest send has completed: its buffer goes.
void RecordSender::retire_oldest_send() {
  pending_bytes_ -= pending_.front().second.size();
  pending_.pop_front();
}

void RecordSender::end_wave() {
  send_held();
  for (auto& p : pending_) MPI_Wait(&p.first, MPI_STATUS_IGNORE);
  pending_.clear();
  pending_bytes_ = 0;
  MPI_Send(nullptr, 0, MPI_BYTE, 0, kTagDone, comm_);
}

// Testing the sends drives their transfer (large batches need rank 0's
// receive and our progress) and frees finished buffers; records held too
// long go if there is room (never waiting here, inside a sample).
void RecordSender::make_progress() {
  while (!pending_.empty()) {
    int done = 0;
    MPI_Test(&pending_.front().first, &done, MPI_STATUS_IGNORE);
    if (!done) break;
    retire_oldest_send();
  }
  if (held_too_long() && room_in_flight()) send_held();
}

}  // namespace treedyn::parallel
