#include "parallel/driver.hpp"

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include "app/exit_codes.hpp"
#include "ensemble/answers.hpp"
#include "ensemble/digest.hpp"
#include "ensemble/ensemble_spec.hpp"
#include "ensemble/sample_job.hpp"
#include "ensemble/sample_runner.hpp"
#include "ensemble/statistics.hpp"
#include "hdf5/ensemble_file.hpp"
#include "job/job_error.hpp"
#include "ensemble/progress.hpp"
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
  std::size_t entries() const { return runner.times() * runner.layout().columns; }
};

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
  unsigned long long length = text.size();
  MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG_LONG, 0, comm);
  text.resize(length);
  MPI_Bcast(text.data(), static_cast<int>(length), MPI_CHAR, 0, comm);
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
int run_nominal(Context& c, const EnsembleOptions& options, std::unique_ptr<EnsembleWriter>& writer,
                std::vector<double>& nominal) {
  int failure = kExitOk;
  if (c.rank == 0) {
    try {
      writer = std::make_unique<EnsembleWriter>(options.output_path, c.job, c.spec, c.runner.layout(),
                                                c.runner.final_state_size());
      const SampleRecord r = c.runner.run(0, true, nominal);
      if (r.status != SampleStatus::ok) {
        std::cerr << c.job.file << ": the nominal run failed: " << r.reason << "\n";
        failure = kExitIntegration;
      }
    } catch (const h5::IoError& e) {
      std::cerr << "error: " << e.what() << "\n";
      failure = kExitIo;
    }
  }
  MPI_Bcast(&failure, 1, MPI_INT, 0, c.comm);
  if (failure != kExitOk) return failure;
  nominal.resize(c.entries());
  MPI_Bcast(nominal.data(), static_cast<int>(c.entries()), MPI_DOUBLE, 0, c.comm);
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
    std::vector<double> trajectory;
    SampleRecord r = run_isolated(c, k, trajectory, sink);
    if (r.status == SampleStatus::ok) {
      for (std::size_t e = 0; e < entries; ++e) {
        low[e] = std::min(low[e], trajectory[e] - nominal[e]);
        high[e] = std::max(high[e], trajectory[e] - nominal[e]);
      }
      pilot.push_back(std::move(trajectory));
    }
    sink.add(std::move(r));
    // Records travel in batches of block_size, as in the sweep.
    if (++in_batch == c.spec.block_size) {
      sink.flush();
      in_batch = 0;
    }
  }
  sink.flush();
  MPI_Allreduce(MPI_IN_PLACE, low.data(), static_cast<int>(entries), MPI_DOUBLE, MPI_MIN, c.comm);
  MPI_Allreduce(MPI_IN_PLACE, high.data(), static_cast<int>(entries), MPI_DOUBLE, MPI_MAX, c.comm);
  ensemble::EnsembleStatistics stats(
      c.runner.times(), columns, c.spec.histogram_bins,
      ensemble::calibrate(nominal, low, high, column_scales(nominal, columns), columns,
                          c.spec.histogram_bins));
  for (const auto& trajectory : pilot) stats.add_sample(trajectory);
  return stats;
}

// Phase 3, sweep: the other samples from the shared queue, in blocks.
void run_sweep(Context& c, ensemble::EnsembleStatistics& stats, RecordSink& sink) {
  WorkQueue queue(c.comm, c.spec.pilot_samples, c.spec.samples, c.spec.block_size);
  std::uint64_t begin = 0, end = 0;
  std::vector<double> trajectory;
  while (queue.next(begin, end)) {
    for (std::uint64_t k = begin; k < end; ++k) {
      SampleRecord r = run_isolated(c, k, trajectory, sink);
      if (r.status == SampleStatus::ok) stats.add_sample(trajectory);
      sink.add(std::move(r));
    }
    sink.flush();
  }
  sink.close();
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

int run(MPI_Comm comm, int rank, int size, const EnsembleOptions& options, const Job& job,
        const ensemble::EnsembleSpec& spec) {
  const auto start = std::chrono::steady_clock::now();
  Context c{comm, rank, size, job, spec, ensemble::SampleRunner(job, spec)};

  std::unique_ptr<EnsembleWriter> writer;
  std::vector<double> nominal;
  if (const int failure = run_nominal(c, options, writer, nominal); failure != kExitOk) return failure;

  ensemble::Progress progress(spec.samples, options.progress_interval, rank == 0 && !options.quiet);
  std::unique_ptr<RecordSink> sink;
  RecordWriter* records = nullptr;  // rank 0's view of the sink
  // Rank 0 keeps every sample's inputs and responses (only when there are responses).
  std::optional<ensemble::ResponseTable> table;
  if (rank == 0 && !spec.responses.empty())
    table.emplace(spec.samples, spec.input_dimensions(), spec.responses.size());
  if (rank == 0) {
    auto w = std::make_unique<RecordWriter>(comm, size, *writer, progress, table ? &*table : nullptr);
    records = w.get();
    sink = std::move(w);
  } else {
    sink = std::make_unique<RecordSender>(comm);
  }

  ensemble::EnsembleStatistics stats = run_pilot(c, nominal, *sink);
  run_sweep(c, stats, *sink);
  EnsembleSummary summary = reduce(c, stats);
  const RunProvenance provenance = gather_provenance(comm, rank, size, options.provenance);

  int failure = kExitOk;
  if (rank == 0) {
    summary.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    summary.failed = records->failed();
    summary.ok = records->done() - summary.failed;
    const std::vector<ensemble::ResponseAnswer> answers =
        table ? ensemble::answer_responses(spec, *table) : std::vector<ensemble::ResponseAnswer>{};
    failure = write_results(*writer, *records, nominal, stats, answers, summary, provenance);
    if (failure != kExitOk) {
      writer.reset();  // removes the temporary file
    } else {
      if (!options.quiet) {
        ensemble::print_digest(std::cout, digest(c, stats, summary));
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
