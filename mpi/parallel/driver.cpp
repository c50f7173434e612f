#include "parallel/driver.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include "app/exit_codes.hpp"
#include "ensemble/answers.hpp"
#include "ensemble/checkpoint.hpp"
#include "ensemble/interruption.hpp"
#include "ensemble/digest.hpp"
#include "ensemble/ensemble_spec.hpp"
#include "ensemble/sample_job.hpp"
#include "ensemble/sample_runner.hpp"
#include "ensemble/statistics.hpp"
#include "hdf5/ensemble_file.hpp"
#include "job/job_error.hpp"
#include "ensemble/progress.hpp"
#include "parallel/memory_check.hpp"
#include "parallel/record_sink.hpp"
#include "parallel/statistics_reduce.hpp"
#include "parallel/work_queue.hpp"

namespace treedyn::parallel {
namespace {

using ensemble::SampleRecord;
using ensemble::SampleStatus;

// Everything a rank needs once the job is known.
struct Context {
  MPI_Comm comm;
  int rank = 0, size = 1;
  const Job& job;
  const ensemble::EnsembleSpec& spec;
  ensemble::SampleRunner runner;
  double busy_seconds = 0.0;
  std::uint64_t samples_run = 0;
  // This rank's checkpoint (none with --checkpoint-every 0, or after a
  // checkpoint write failed: the run goes on without).
  std::unique_ptr<ensemble::RankCheckpoint> checkpoint{};
  double checkpoint_every = 0.0;
  std::chrono::steady_clock::time_point last_checkpoint = std::chrono::steady_clock::now();
  // The samples this run owns: [first, end), the whole ensemble unless a part.
  std::uint64_t first = 0, end = 0;
  bool in_range(std::uint64_t k) const { return k >= first && k < end; }
  std::uint64_t owned() const { return end - first; }
  // Samples a resumed run already has, [first, end) intervals, sorted.
  std::vector<std::pair<std::uint64_t, std::uint64_t>> finished{};
  std::size_t entries() const { return runner.times() * runner.layout().columns; }
  bool is_finished(std::uint64_t k) const {
    auto it = std::upper_bound(finished.begin(), finished.end(), k,
                               [](std::uint64_t v, const auto& interval) { return v < interval.first; });
    return it != finished.begin() && k < std::prev(it)->second;
  }
};

// A record goes to rank 0 and into this rank's checkpoint.
void keep(Context& c, ensemble::SampleRecord r, RecordSink& sink) {
  if (c.checkpoint) c.checkpoint->add(r);
  sink.add(std::move(r));
}

// Writes this rank's checkpoint (its statistics count exactly the ok records
// kept so far). A failure is reported once and turns checkpoints off here.
bool save_checkpoint(Context& c, ensemble::EnsembleStatistics& stats) {
  if (!c.checkpoint) return false;
  try {
    c.checkpoint->save(stats);
    c.last_checkpoint = std::chrono::steady_clock::now();
    return true;
  } catch (const ensemble::CheckpointError& e) {
    std::cerr << "warning: rank " << c.rank << ": " << e.what() << "; checkpoints are off for this rank\n";
    c.checkpoint.reset();
    return false;
  }
}

void checkpoint_if_due(Context& c, ensemble::EnsembleStatistics& stats) {
  if (!c.checkpoint) return;
  const double since = std::chrono::duration<double>(std::chrono::steady_clock::now() - c.last_checkpoint).count();
  if (since >= c.checkpoint_every) save_checkpoint(c, stats);
}

// The same vector on every rank (rank 0's), in chunks: MPI counts are ints.
template <class T>
void broadcast(MPI_Comm comm, std::vector<T>& v) {
  unsigned long long size = v.size();
  MPI_Bcast(&size, 1, MPI_UNSIGNED_LONG_LONG, 0, comm);
  v.resize(size);
  constexpr std::size_t kChunk = std::size_t{1} << 24;
  const std::size_t bytes = size * sizeof(T);
  auto* data = reinterpret_cast<char*>(v.data());
  for (std::size_t first = 0; first < bytes; first += kChunk)
    MPI_Bcast(data + first, static_cast<int>(std::min(kChunk, bytes - first)), MPI_BYTE, 0, comm);
}

template <class T>
void broadcast(MPI_Comm comm, std::vector<T>& v);

// Rank 0's file text to everyone (or an error text and a failed flag).
bool share_job_text(MPI_Comm comm, int rank, const std::string& path, std::string& text) {
  int ok = 1;
  if (rank == 0) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
      ok = 0;
      text = path + ": cannot open the job file for reading";
    } else {
      std::ostringstream s;
      s << in.rdbuf();
      text = s.str();
    }
  }
  MPI_Bcast(&ok, 1, MPI_INT, 0, comm);
  std::vector<char> bytes(text.begin(), text.end());
  broadcast(comm, bytes);
  text.assign(bytes.begin(), bytes.end());
  return ok != 0;
}

// A sample never takes the job down: any exception becomes a failed record.
// `sink.poll()` runs at every output time, so MPI progresses meanwhile.
SampleRecord run_isolated(Context& c, std::uint64_t k, std::vector<double>& trajectory,
                          RecordSink& sink) {
  const auto start = std::chrono::steady_clock::now();
  SampleRecord r;
  try {
    r = c.runner.run(k, false, trajectory, [&] { sink.poll(); });
  } catch (const std::exception& e) {
    r = c.runner.failed_record(k, ensemble::SampleStatus::integration_failed,
                               std::string("internal error: ") + e.what());
  }
  c.busy_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ++c.samples_run;
  return r;
}

// Element-wise all-reduce of doubles in chunks (MPI counts are ints).
void all_reduce(MPI_Comm comm, std::vector<double>& v, MPI_Op op) {
  constexpr std::size_t kChunk = std::size_t{1} << 26;
  for (std::size_t first = 0; first < v.size(); first += kChunk)
    MPI_Allreduce(MPI_IN_PLACE, v.data() + first, static_cast<int>(std::min(kChunk, v.size() - first)),
                  MPI_DOUBLE, op, comm);
}

// Per-column largest |nominal| over time: the fallback fixed-point unit.
std::vector<double> column_scales(const std::vector<double>& nominal, std::size_t columns) {
  std::vector<double> scale(columns, 0.0);
  for (std::size_t e = 0; e < nominal.size(); ++e)
    scale[e % columns] = std::max(scale[e % columns], std::abs(nominal[e]));
  return scale;
}

// The end-of-run summary (ensemble/digest.hpp): counts and rate, then the
// final-time mean, spread and outer quantile band of a few telling columns.
ensemble::EnsembleDigest digest(const Context& c, const ensemble::EnsembleStatistics& s,
                                const EnsembleSummary& summary) {
  const auto& layout = c.runner.layout();
  const std::size_t last = c.runner.times() - 1;
  ensemble::EnsembleDigest d;
  d.samples = c.spec.samples;
  d.ok = summary.ok;
  d.failed = summary.failed;
  d.ranks = c.size;
  d.wall_seconds = summary.wall_seconds;
  d.last_time = c.job.request.output_times[last];
  d.low_probability = *std::min_element(c.spec.quantiles.begin(), c.spec.quantiles.end());
  d.high_probability = *std::max_element(c.spec.quantiles.begin(), c.spec.quantiles.end());
  for (auto [q, k] : ensemble::digest_columns(layout, c.job.model.n)) {
    const std::size_t e = last * layout.columns + layout.offset[q] + k;
    d.lines.push_back({layout.quantity[q], layout.names[q][k], s.mean(e), s.std_dev(e),
                       s.quantile(e, d.low_probability), s.quantile(e, d.high_probability)});
  }
  return d;
}

// Phase 1, nominal: rank 0 opens the output (temporary name) before any
// work, then integrates the nominal run, the centre of the statistics, and
// sends it to everyone. Returns an exit code, the same on every rank.
// A resumed run (`restored`) takes the nominal run from its checkpoint.
int run_nominal(Context& c, const EnsembleOptions& options, std::unique_ptr<EnsembleWriter>& writer,
                std::vector<double>& nominal, bool restored) {
  int failure = kExitOk;
  if (c.rank == 0) {
    try {
      if (!options.part())
        writer = std::make_unique<EnsembleWriter>(options.output_path, c.job, c.spec, c.runner.layout(),
                                                  c.runner.final_state_size());
      catch_interruptions();  // over the writer's remove-on-signal guard: stop cleanly instead
      if (!restored) {
        const SampleRecord r = c.runner.run(0, true, nominal);
        if (r.status != SampleStatus::ok) {
          std::cerr << c.job.file << ": the nominal run failed: " << r.reason << "\n";
          failure = kExitIntegration;
        }
      }
    } catch (const h5::IoError& e) {
      std::cerr << "error: " << e.what() << "\n";
      failure = kExitIo;
    }
  }
  MPI_Bcast(&failure, 1, MPI_INT, 0, c.comm);
  if (failure != kExitOk) return failure;
  broadcast(c.comm, nominal);
  return kExitOk;
}

// Phase 2, pilot and calibration: samples 0..pilot-1, round-robin; the
// all-reduced minima and maxima of their deviations from the nominal run fix
// every rank's fixed-point scales and histogram ranges, then they count.
ensemble::EnsembleStatistics run_pilot(Context& c, const std::vector<double>& nominal,
                                       RecordSink& sink) {
  const std::size_t columns = c.runner.layout().columns, entries = c.entries();
  std::vector<std::vector<double>> pilot;
  std::vector<double> low(entries, std::numeric_limits<double>::infinity());
  std::vector<double> high(entries, -std::numeric_limits<double>::infinity());
  std::uint64_t in_batch = 0;
  for (std::uint64_t k = static_cast<std::uint64_t>(c.rank); k < c.spec.pilot_samples;
       k += static_cast<std::uint64_t>(c.size)) {
    if (interruption_signal() != 0) break;  // nothing is resumable before the calibration
    std::vector<double> trajectory;
    SampleRecord r = run_isolated(c, k, trajectory, sink);
    // Every part runs every pilot sample (the calibration must be the same
    // in all parts), but keeps and counts only those of its range.
    if (r.status == SampleStatus::ok) {
      for (std::size_t e = 0; e < entries; ++e) {
        low[e] = std::min(low[e], trajectory[e] - nominal[e]);
        high[e] = std::max(high[e], trajectory[e] - nominal[e]);
      }
      if (c.in_range(k)) pilot.push_back(std::move(trajectory));
    }
    if (c.in_range(k)) keep(c, std::move(r), sink);
    // Records travel in batches of block_size, as in the sweep.
    if (++in_batch == c.spec.block_size) {
      sink.flush();
      in_batch = 0;
    }
  }
  sink.flush();
  all_reduce(c.comm, low, MPI_MIN);
  all_reduce(c.comm, high, MPI_MAX);
  ensemble::EnsembleStatistics stats(
      c.runner.times(), columns, c.spec.histogram_bins,
      ensemble::calibrate(nominal, low, high, column_scales(nominal, columns), columns,
                          c.spec.histogram_bins));
  for (const auto& trajectory : pilot) stats.add_sample(trajectory);
  return stats;
}

// Phase 3, sweep: the other samples from the shared queue, in blocks (a
// resumed run: every sample it does not have yet). A signal stops it after
// the sample in flight, on every rank. Returns whether it was interrupted.
bool run_sweep(Context& c, std::uint64_t first, ensemble::EnsembleStatistics& stats, RecordSink& sink) {
  WorkQueue queue(c.comm, first, c.end, c.spec.block_size);
  std::uint64_t begin = 0, end = 0;
  std::vector<double> trajectory;
  bool stop = false;
  while (!stop && queue.next(begin, end)) {
    for (std::uint64_t k = begin; k < end; ++k) {
      if (interruption_signal() != 0) queue.interrupt();
      if (queue.interrupted()) {
        stop = true;
        break;
      }
      if (c.is_finished(k)) continue;
      SampleRecord r = run_isolated(c, k, trajectory, sink);
      if (r.status == SampleStatus::ok) stats.add_sample(trajectory);
      keep(c, std::move(r), sink);
    }
    sink.flush();
    if (!stop) checkpoint_if_due(c, stats);
  }
  if (interruption_signal() != 0) queue.interrupt();
  const bool interrupted = queue.interrupted();
  sink.close();
  return interrupted;
}

// Phase 4, reduction: the statistics summed onto rank 0 exactly, and every
// rank's load and memory gathered there.
EnsembleSummary reduce(Context& c, ensemble::EnsembleStatistics& stats) {
  reduce_statistics(c.comm, stats);
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const double mine[3] = {static_cast<double>(usage.ru_maxrss) / 1024.0,
                          static_cast<double>(c.samples_run), c.busy_seconds};
  std::vector<double> all(3 * static_cast<std::size_t>(c.size));
  MPI_Gather(mine, 3, MPI_DOUBLE, all.data(), 3, MPI_DOUBLE, 0, c.comm);
  EnsembleSummary summary;
  summary.ranks = c.size;
  for (int r = 0; r < c.size && c.rank == 0; ++r) {
    summary.peak_rss_mib.push_back(all[3 * r]);
    summary.samples_per_rank.push_back(static_cast<long long>(all[3 * r + 1]));
    summary.busy_seconds.push_back(all[3 * r + 2]);
  }
  return summary;
}

// Every rank's host name and the MPI library, for the file's provenance.
RunProvenance gather_provenance(MPI_Comm comm, int rank, int size, RunProvenance run) {
  char name[MPI_MAX_PROCESSOR_NAME] = {};
  int length = 0;
  MPI_Get_processor_name(name, &length);
  std::vector<char> all(static_cast<std::size_t>(size) * MPI_MAX_PROCESSOR_NAME, '\0');
  MPI_Gather(name, MPI_MAX_PROCESSOR_NAME, MPI_CHAR, all.data(), MPI_MAX_PROCESSOR_NAME, MPI_CHAR, 0, comm);
  run.ranks = size;
  for (int r = 0; r < size && rank == 0; ++r)
    run.rank_hosts.emplace_back(all.data() + static_cast<std::size_t>(r) * MPI_MAX_PROCESSOR_NAME);
  char library[MPI_MAX_LIBRARY_VERSION_STRING] = {};
  MPI_Get_library_version(library, &length);
  run.mpi_library = std::string(library, static_cast<std::size_t>(length));
  while (!run.mpi_library.empty() && (run.mpi_library.back() == '\n' || run.mpi_library.back() == '\0'))
    run.mpi_library.pop_back();
  return run;
}

// Phase 5, write (rank 0): the nominal run, the statistics and the run's
// attributes, then the rename into place. Returns an exit code.
int write_results(EnsembleWriter& writer, const RecordWriter& records,
                  const std::vector<double>& nominal, const ensemble::EnsembleStatistics& stats,
                  const std::vector<ensemble::ResponseAnswer>& answers, const EnsembleSummary& summary,
                  const RunProvenance& run) {
  try {
    if (!records.io_error().empty()) throw h5::IoError(records.io_error());
    writer.write_nominal(nominal);
    writer.write_statistics(stats);
    writer.write_answers(answers);
    writer.finish(summary, run);
  } catch (const h5::IoError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitIo;
  }
  return kExitOk;
}

// What this run's records look like (a loaded checkpoint must match).
ensemble::RecordShape record_shape(const Context& c) {
  ensemble::RecordShape shape;
  shape.first = c.first;
  shape.end = c.end;
  shape.inputs = c.spec.input_dimensions();
  shape.reductions = c.spec.per_sample.size() * c.runner.layout().columns;
  shape.responses = c.spec.responses.size();
  shape.final_state = c.runner.final_state_size();
  shape.trajectory = c.entries();
  shape.stored = c.spec.store_trajectories;
  return shape;
}

// Phase 0 (rank 0): stale temporary files of dead processes, then the
// checkpoint: loaded with --resume; refused without it (a fresh run must not
// mix with an earlier run's parts); a fresh run starts an empty directory.
// Returns an exit code, the same on every rank.
int open_checkpoint(Context& c, const EnsembleOptions& options, const ensemble::CheckpointIdentity& id,
                    std::optional<ensemble::RestoredRun>& restored) {
  namespace fs = std::filesystem;
  int code = kExitOk;
  if (c.rank == 0) {
    const fs::path output(options.output_path);
    const fs::path dir = ensemble::checkpoint_directory(output);
    std::vector<std::string> stale = ensemble::remove_stale_temporaries(output.parent_path(), output.filename().string());
    std::error_code ec;
    if (fs::is_directory(dir, ec))
      for (auto& f : ensemble::remove_stale_temporaries(dir, "")) stale.push_back(std::move(f));
    for (const std::string& f : stale)
      std::cerr << "note: removed " << f << ", a temporary file left by a process that no longer runs\n";
    try {
      if (options.resume) {
        restored = ensemble::load_checkpoint(dir, id, c.entries(), c.spec.histogram_bins, record_shape(c));
        if (!restored)
          std::cerr << "note: no checkpoint " << dir.string() << " to resume (or it was written before the pilot "
                    << "samples were done): starting from the beginning\n";
      } else if (fs::exists(dir / "common.state", ec) || ec) {
        if (ec)
          std::cerr << "error: cannot look into " << dir.string() << ": " << ec.message() << "\n";
        else
          std::cerr << "error: " << dir.string() << " holds the checkpoint of an earlier run of this output: "
                    << "resume it with --resume, or remove that directory to start afresh\n";
        code = ec ? kExitIo : kExitBadInput;
      }
    } catch (const ensemble::CheckpointError& e) {
      std::cerr << "error: " << e.what() << "\n";
      code = kExitBadInput;
    }
    if (code == kExitOk && !restored && options.checkpoint_every > 0.0) {
      ensemble::remove_checkpoint(dir);
      fs::create_directories(dir, ec);
      if (ec) {
        std::cerr << "error: cannot create the checkpoint directory " << dir.string() << ": " << ec.message()
                  << " (or turn checkpoints off with --checkpoint-every 0)\n";
        code = kExitIo;
      }
    }
  }
  MPI_Bcast(&code, 1, MPI_INT, 0, c.comm);
  return code;
}

// What a resumed run's ranks need from rank 0's checkpoint.
void share_restored(Context& c, std::optional<ensemble::RestoredRun>& restored) {
  int have = c.rank == 0 && restored ? 1 : 0;
  MPI_Bcast(&have, 1, MPI_INT, 0, c.comm);
  if (!have) return;
  if (c.rank != 0) restored.emplace();
  ensemble::Calibration& cal = restored->calibration;
  for (auto* v : {&cal.center, &cal.scale, &cal.low, &cal.width}) broadcast(c.comm, *v);
  std::vector<std::uint64_t> flat;
  for (const auto& [a, b] : restored->finished) {
    flat.push_back(a);
    flat.push_back(b);
  }
  broadcast(c.comm, flat);
  c.finished.clear();
  for (std::size_t k = 0; k + 1 < flat.size(); k += 2) c.finished.emplace_back(flat[k], flat[k + 1]);
}

// Sum of a count over the ranks, on every rank.
std::uint64_t sum_over_ranks(MPI_Comm comm, std::uint64_t mine) {
  MPI_Allreduce(MPI_IN_PLACE, &mine, 1, MPI_UINT64_T, MPI_SUM, comm);
  return mine;
}

bool any_rank(MPI_Comm comm, bool mine) {
  int flag = mine ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &flag, 1, MPI_INT, MPI_MAX, comm);
  return flag != 0;
}

// A signal stopped the run: every rank writes its checkpoint, rank 0 removes
// the temporary output and says how far it got. Exit 5 on every rank.
int stop_interrupted(Context& c, ensemble::EnsembleStatistics& stats, std::unique_ptr<EnsembleWriter>& writer,
                     std::uint64_t restored_samples, bool resumable, const std::string& output) {
  const bool saved = resumable && save_checkpoint(c, stats);
  const bool all_saved = !any_rank(c.comm, resumable && !saved);
  const std::uint64_t kept = sum_over_ranks(c.comm, saved ? c.checkpoint->saved_records() : 0) + restored_samples;
  int signal_number = interruption_signal();
  MPI_Allreduce(MPI_IN_PLACE, &signal_number, 1, MPI_INT, MPI_MAX, c.comm);
  if (c.rank == 0) {
    writer.reset();  // removes the temporary output
    const char* what = signal_number == SIGINT    ? "SIGINT"
                       : signal_number == SIGTERM ? "SIGTERM"
                       : signal_number == SIGUSR1 ? "SIGUSR1"
                                                  : "a signal";
    const std::string dir = ensemble::checkpoint_directory(output).string();
    if (!resumable) {
      std::cerr << "interrupted by " << what << " during the pilot samples: nothing to resume yet; run it again\n";
      ensemble::remove_checkpoint(dir);
    } else if (c.checkpoint_every <= 0.0) {
      std::cerr << "interrupted by " << what << "; checkpoints are off (--checkpoint-every 0, or a checkpoint "
                << "could not be written), so this run's samples are not kept\n";
    } else if (!all_saved) {
      std::cerr << "interrupted by " << what << "; a rank could not write its checkpoint (see above): --resume "
                << "keeps what " << dir << " holds\n";
    } else {
      std::cerr << "interrupted by " << what << " after " << kept << " of " << c.owned()
                << " samples; resume with --resume (checkpoint " << dir << ")\n";
    }
  }
  return kExitInterrupted;
}

// The end of a part (rank 0): its records, statistics and calibration into
// the part file, atomically.
int write_part(Context& c, const EnsembleOptions& options, const ensemble::CheckpointIdentity& job_id,
               const std::vector<double>& nominal, ensemble::EnsembleStatistics& stats, const RecordWriter& records,
               std::vector<SampleRecord> part_records) {
  if (!records.io_error().empty()) {
    std::cerr << "error: " << records.io_error() << "\n";
    return kExitIo;
  }
  std::sort(part_records.begin(), part_records.end(),
            [](const SampleRecord& a, const SampleRecord& b) { return a.index < b.index; });
  ensemble::PartFile part;
  part.id = job_id;
  part.job_text = c.job.text;
  part.job_path = options.job_path;
  part.first = c.first;
  part.end = c.end;
  part.nominal = nominal;
  part.calibration = stats.calibration();
  part.records = std::move(part_records);
  try {
    ensemble::write_part_file(options.output_path, part, stats);
  } catch (const ensemble::CheckpointError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitIo;
  }
  if (!options.quiet)
    std::cout << "part: samples " << c.first << " .. " << c.end - 1 << " of " << c.spec.samples << ", "
              << records.failed() << " failed\n";
  std::printf("wrote %s (merge the parts with: treedyn-ensemble merge -o OUT.h5 PART ...)\n",
              options.output_path.c_str());
  return kExitOk;
}

int run(MPI_Comm comm, int rank, int size, const EnsembleOptions& options, const Job& job,
        const ensemble::EnsembleSpec& spec) {
  const auto start = std::chrono::steady_clock::now();
  catch_interruptions();
  Context c{comm, rank, size, job, spec, ensemble::SampleRunner(job, spec)};
  c.checkpoint_every = options.checkpoint_every;
  c.first = options.part() ? options.first_sample : 0;
  c.end = options.part() ? options.end_sample : spec.samples;
  if (c.first >= c.end || c.end > spec.samples) {
    if (rank == 0)
      std::cerr << "error: --samples " << options.first_sample << ":" << options.end_sample
                << " is not a range of this ensemble's sample indices: FIRST < END <= " << spec.samples << "\n";
    return kExitBadInput;
  }
  // A part's checkpoint belongs to its range; the part file to the job.
  const ensemble::CheckpointIdentity job_id = ensemble::checkpoint_identity(job.text, build_identity());
  const ensemble::CheckpointIdentity id =
      options.part() ? ensemble::checkpoint_identity(job.text + "\n# --samples " + std::to_string(c.first) + ":" +
                                                         std::to_string(c.end),
                                                     build_identity())
                     : job_id;
  const auto checkpoint_dir = ensemble::checkpoint_directory(options.output_path);

  if (!memory_fits(comm, ensemble::statistics_bytes(job, spec))) return kExitMemory;

  std::optional<ensemble::RestoredRun> restored;
  if (const int code = open_checkpoint(c, options, id, restored); code != kExitOk) return code;
  share_restored(c, restored);

  std::unique_ptr<EnsembleWriter> writer;
  std::vector<double> nominal;
  if (rank == 0 && restored) nominal = restored->nominal;
  if (const int failure = run_nominal(c, options, writer, nominal, restored.has_value()); failure != kExitOk)
    return failure;

  ensemble::Progress progress(c.owned(), options.progress_interval, rank == 0 && !options.quiet);
  std::unique_ptr<RecordSink> sink;
  RecordWriter* records = nullptr;  // rank 0's view of the sink
  std::vector<SampleRecord> part_records;  // a part's records (rank 0)
  // Rank 0 keeps every sample's inputs and responses (only when there are responses).
  std::optional<ensemble::ResponseTable> table;
  if (rank == 0 && !spec.responses.empty() && !options.part())
    table.emplace(spec.samples, spec.input_dimensions(), spec.responses.size());
  if (rank == 0) {
    auto w = std::make_unique<RecordWriter>(comm, size, writer.get(), progress, table ? &*table : nullptr,
                                            options.part() ? &part_records : nullptr);
    records = w.get();
    sink = std::move(w);
  } else {
    sink = std::make_unique<RecordSender>(comm);
  }

  // The calibration: from the pilot samples, or from the checkpoint. A
  // resumed run's restored statistics stay apart (rank 0) until the end, so
  // that this run's checkpoints hold only this run's samples.
  std::uint64_t generation = 0, restored_samples = 0;
  std::optional<ensemble::EnsembleStatistics> stats, restored_stats;
  int code = kExitOk;
  if (restored) {
    stats.emplace(c.runner.times(), c.runner.layout().columns, spec.histogram_bins, restored->calibration);
    if (rank == 0) {
      restored_stats.emplace(*stats);
      ensemble::restore_statistics(restored->statistics, *restored_stats);
      restored_samples = restored->records.size();
      try {
        generation = ensemble::consolidate_checkpoint(checkpoint_dir, id, *restored, *restored_stats);
      } catch (const ensemble::CheckpointError& e) {
        std::cerr << "error: " << e.what() << "\n";
        code = kExitIo;
      }
      std::cerr << "resuming: " << restored_samples << " of " << c.owned() << " samples from "
                << checkpoint_dir.string() << "\n";
      records->restore(std::move(restored->records));
    }
    MPI_Bcast(&code, 1, MPI_INT, 0, comm);
    if (code != kExitOk) return code;
    MPI_Bcast(&generation, 1, MPI_UINT64_T, 0, comm);
    restored_samples = sum_over_ranks(comm, restored_samples);
  }
  if (options.checkpoint_every > 0.0)
    c.checkpoint = std::make_unique<ensemble::RankCheckpoint>(checkpoint_dir, id, generation,
                                                              "rank" + std::to_string(rank));
  if (!restored) {
    stats.emplace(run_pilot(c, nominal, *sink));
    const bool pilot_complete = !any_rank(comm, interruption_signal() != 0);
    if (!pilot_complete) {
      sink->close();
      return stop_interrupted(c, *stats, writer, 0, false, options.output_path);
    }
    int common_written = 1;
    if (rank == 0 && c.checkpoint) {
      try {
        ensemble::write_checkpoint_common(checkpoint_dir, id, nominal, stats->calibration());
      } catch (const ensemble::CheckpointError& e) {
        std::cerr << "warning: " << e.what() << "; the run goes on without checkpoints\n";
        common_written = 0;
      }
    }
    // Parts without common.state could never be loaded: none, then.
    MPI_Bcast(&common_written, 1, MPI_INT, 0, comm);
    if (!common_written) {
      c.checkpoint.reset();
      c.checkpoint_every = 0.0;
    } else {
      checkpoint_if_due(c, *stats);  // the pilot may have taken longer than the interval
    }
  }
  const bool interrupted =
      run_sweep(c, restored ? c.first : std::max(c.first, std::min<std::uint64_t>(spec.pilot_samples, c.end)), *stats,
                *sink);
  if (any_rank(comm, interrupted))
    return stop_interrupted(c, *stats, writer, restored_samples, true, options.output_path);

  if (restored_stats) stats->merge(*restored_stats);
  EnsembleSummary summary = reduce(c, *stats);
  const RunProvenance provenance = gather_provenance(comm, rank, size, options.provenance);

  int failure = kExitOk;
  if (rank == 0 && options.part()) {
    failure = write_part(c, options, job_id, nominal, *stats, *records, std::move(part_records));
    if (failure == kExitOk) ensemble::remove_checkpoint(checkpoint_dir);
  } else if (rank == 0) {
    summary.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    summary.failed = records->failed();
    summary.ok = records->done() - summary.failed;
    const std::vector<ensemble::ResponseAnswer> answers =
        table ? ensemble::answer_responses(spec, *table) : std::vector<ensemble::ResponseAnswer>{};
    failure = write_results(*writer, *records, nominal, *stats, answers, summary, provenance);
    if (failure != kExitOk) {
      writer.reset();  // removes the temporary file; the checkpoint stays for --resume
    } else {
      ensemble::remove_checkpoint(checkpoint_dir);
      // The processes of a run killed just before this one are gone by now.
      const std::filesystem::path output(options.output_path);
      for (const std::string& f :
           ensemble::remove_stale_temporaries(output.parent_path(), output.filename().string()))
        std::cerr << "note: removed " << f << ", a temporary file left by a process that no longer runs\n";
      if (!options.quiet) {
        ensemble::print_digest(std::cout, digest(c, *stats, summary));
        ensemble::print_response_summary(std::cout, spec, answers);
      }
      std::printf("wrote %s\n", options.output_path.c_str());
    }
  }
  MPI_Bcast(&failure, 1, MPI_INT, 0, comm);
  return failure;
}

}  // namespace

int run_ensemble(MPI_Comm comm, const EnsembleOptions& options) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  std::string text;
  if (!share_job_text(comm, rank, options.job_path, text)) {
    if (rank == 0) std::cerr << "error: " << text << "\n";
    return kExitBadInput;
  }
  // Every rank parses the same text: the same error everywhere, no collective
  // left waiting.
  Job job;
  ensemble::EnsembleSpec spec;
  try {
    job = parse_job(text, options.job_path);
    ensemble::apply_sample_section(job);
    spec = ensemble::read_ensemble(job);
  } catch (const JobError& e) {
    if (rank == 0) std::cerr << "error: " << e.what() << "\n";
    return kExitBadInput;
  }
  return run(comm, rank, size, options, job, spec);
}

}  // namespace treedyn::parallel
