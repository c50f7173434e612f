// Where finished per-sample records go: rank 0 writes them (its own and
// everyone else's, by sample index); the other ranks send them to rank 0 in
// bounded batches. Both keep MPI progressing when poll() is called during
// long integrations, so the work queue and the messages never wait for a
// rank that is busy integrating.
#pragma once

#include <mpi.h>

#include <chrono>
#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "common/buffer_pool.hpp"
#include "common/host_time.hpp"
#include "ensemble/progress.hpp"
#include "ensemble/response_table.hpp"
#include "hdf5/ensemble_file.hpp"
#include "hdf5/unit_chunks.hpp"
#include "output/sample_record.hpp"

namespace treedyn::parallel {

class RecordSink {
 public:
  virtual ~RecordSink() = default;
  virtual void add(SampleRecord record) = 0;
  // Around the samples [first, first + rows) of one unit
  // (hdf5/unit_chunks.hpp: a whole chunk of every per-sample dataset, run
  // here): a sender holds their records and, when every one of them was
  // added, sends them as one unit of compressed chunks. A unit a stop cut
  // short (`stopped`) is dropped: the stopped run's output is removed, and
  // its records are in this rank's checkpoint already (RankResults::keep),
  // so rank 0 need not take in up to a unit per rank inside the launcher's
  // SIGTERM-to-SIGKILL window. Otherwise a unit short of rows goes as
  // records. Rank 0 writes its own records as they come.
  virtual void begin_unit(std::uint64_t first, std::uint64_t rows) {
    (void)first;
    (void)rows;
  }
  virtual void end_unit(bool stopped) { (void)stopped; }
  // At the end of each block of samples: rank 0 counts its own records;
  // the others send theirs when enough are held (RecordSender).
  virtual void end_block() = 0;
  // Cheap, called often (every output time): lets MPI make progress.
  void poll();
  // After a wave's last block, on every rank: rank 0 returns once every
  // rank has ended the wave, so it then holds every record of the wave.
  virtual void end_wave() = 0;
  // Time spent writing records: rank 0 receiving, decoding and writing
  // every rank's records (inside poll() too, so a sample's busy time can
  // leave it out); 0 on the other ranks, which encode their records as part
  // of the sample (keep()) and hand them to MPI in batches (RecordSender).
  double writing_seconds() const { return writing_seconds_; }
  // ... as CPU time of this thread (thread_cpu_seconds()).
  double writing_cpu_seconds() const { return writing_cpu_seconds_; }

 protected:
  virtual void make_progress() = 0;

  // Counts the scope's time into writing_seconds(); nested scopes count once.
  class Writing {
   public:
    explicit Writing(RecordSink& sink);
    ~Writing();
    Writing(const Writing&) = delete;
    Writing& operator=(const Writing&) = delete;

   private:
    RecordSink& sink_;
    std::chrono::steady_clock::time_point start_;
    double start_cpu_ = 0.0;
  };

 private:
  std::int64_t last_poll_ns_ = 0;  // CLOCK_MONOTONIC_COARSE
  double writing_seconds_ = 0.0, writing_cpu_seconds_ = 0.0;
  int writing_depth_ = 0;
};

// Rank 0. An error while writing (I/O, or HDF5's memory) is kept, the run
// goes on so no rank waits for rank 0 forever, and it is reported at the end
// (exit 4). Records are counted (progress, `table`) as they arrive but go to
// the file in batches, once those held pass 4 MiB or 4096 records (checked
// after each message, so a batch may pass them by one message): every write
// touches each of the /samples datasets once, so a few rows at a time cost
// rank 0 time in which it runs no sample (BENCHMARKS.md, "Two ranks: rank 0
// writes the records in batches"). The batch is bounded: memory does not
// grow with N.
class RecordWriter final : public RecordSink {
 public:
  // Every record also goes into `table` (status, inputs, responses), if
  // given, for the answers computed at the end. A part of a split ensemble
  // has no `writer` (null): its records are `collected` for the part file.
  RecordWriter(MPI_Comm comm, int ranks, h5::EnsembleWriter* writer, ensemble::Progress& progress,
               ensemble::ResponseTable* table, std::vector<SampleRecord>* collected = nullptr);
  void add(SampleRecord record) override;
  void end_block() override;
  void end_wave() override;
  // The progress line's last word (at the end of the run, or of a stop).
  void finish_progress() { progress_.finish(done_, failed_); }
  // Records of a resumed run's checkpoint, written as if they had arrived.
  void restore(std::vector<SampleRecord> records) {
    const Writing writing(*this);
    write(std::move(records));
  }
  // The records held, into the file (or collected): after the last wave,
  // before the output is completed.
  void write_held();
  std::uint64_t done() const { return done_; }
  std::uint64_t failed() const { return failed_; }
  // Of done(): the samples that came in units; and the CPU time (of
  // writing_cpu_seconds()) rank 0 spent storing them: decoding, the direct
  // chunk writes, counting; the rest of it receiving (MPI) or on records.
  std::uint64_t done_in_units() const { return done_in_units_; }
  double unit_storing_cpu_seconds() const { return unit_storing_cpu_seconds_; }
  const std::string& io_error() const { return io_error_; }

 private:
  void make_progress() override { drain(false); }
  void drain(bool wait);
  void post_arrived();
  void post(MPI_Message& message, const MPI_Status& status);
  bool complete_received(bool wait);
  void handle(std::span<const char> message, int source, int tag);
  void write(std::vector<SampleRecord> records);
  void count(const SampleRecord& record);
  void write_unit(std::span<const char> message, int source);

  // A message matched and being received (MPI_Imrecv): rank 0 never waits
  // in a receive for a sender busy with a sample (a message past MPI's
  // eager limit needs its sender's progress too), it goes on and takes the
  // message at a later poll.
  struct Receiving {
    ByteBuffer bytes;
    int count = 0, source = 0, tag = 0;
  };

  MPI_Comm comm_;
  int ranks_;
  h5::EnsembleWriter* writer_;
  ensemble::Progress& progress_;
  ensemble::ResponseTable* table_;
  std::vector<SampleRecord>* collected_;
  std::vector<SampleRecord> local_;
  std::vector<SampleRecord> batch_;    // counted, not yet in the file
  std::vector<Receiving> receiving_;   // posted, in the order matched
  std::vector<MPI_Request> requests_;  // theirs, in the same order
  std::size_t receiving_bytes_ = 0;    // of the messages in receiving_
  h5::Unit unit_;                      // the last unit received, decoded (its vectors reused)
  BufferPool spare_;                   // buffers of completed messages, reused: no allocation per message
  std::size_t batch_bytes_ = 0;
  int finished_ranks_ = 0;
  std::uint64_t done_ = 0, failed_ = 0, done_in_units_ = 0;
  double unit_storing_cpu_seconds_ = 0.0;
  std::string io_error_;
};

// Ranks other than 0: records encoded as they are kept and sent to rank 0
// in messages of several blocks (see message_bytes and kMaxHoldSeconds in
// record_sink.cpp), and at a wave's end whatever their size.
class RecordSender final : public RecordSink {
 public:
  // `rows`: the per-sample rows' layout, for units (none: every record is
  // sent as a record).
  RecordSender(MPI_Comm comm, int ranks, std::optional<ensemble::SampleRows> rows);
  RecordSender(const RecordSender&) = delete;  // its encoder refers to its rows
  RecordSender& operator=(const RecordSender&) = delete;
  void add(SampleRecord record) override;
  void begin_unit(std::uint64_t first, std::uint64_t rows) override;
  void end_unit(bool stopped) override;
  void end_block() override;
  void end_wave() override;

 private:
  void send(std::vector<char> message, int tag);
  void make_progress() override;
  bool held_too_long() const;
  bool room_in_flight() const;
  void send_held();  // waits for room in flight first
  void retire_oldest_send();

  MPI_Comm comm_;
  std::size_t send_bytes_;                            // a message's size: records held until they make it
  std::vector<char> batch_;                           // encoded records not yet sent
  std::chrono::steady_clock::time_point held_since_;  // when batch_'s first record came
  std::deque<std::pair<MPI_Request, std::vector<char>>> pending_;
  std::size_t pending_bytes_ = 0;  // of the batches in `pending_`
  std::optional<ensemble::SampleRows> rows_;
  std::optional<h5::UnitEncoder> encoder_;
  bool in_unit_ = false;
  std::uint64_t unit_first_ = 0, unit_rows_ = 0;
  std::vector<SampleRecord> unit_;  // the unit's records so far
};

}  // namespace treedyn::parallel
