// The phases that run samples: the nominal run, the waves of the design
// (the pilot wave first), and the stop when a signal cuts them short.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <thread>

#include "common/exit_codes.hpp"
#include "common/host_time.hpp"
#include "designs/design_rules.hpp"
#include "ensemble/capacity.hpp"
#include "ensemble/sample_rows.hpp"
#include "parallel/collectives.hpp"
#include "parallel/driver.hpp"
#include "parallel/work_queue.hpp"
#include "process/atomic_file.hpp"
#include "process/signals.hpp"

namespace treedyn::parallel {
namespace {

using Sync = process::AtomicFile::Sync;

// One sample. Any exception becomes a failed record: a sample never takes
// the job down. At every output time the record transport progresses, and
// a stop signal abandons the sample (nullopt: a resumed run runs it again).
// Busy time is the sample's own: rank 0's writing of records that arrive
// meanwhile counts as writing (RecordSink::writing_seconds), not as busy.
// `uniforms`: the run's own uniform numbers (a chain's), else the design's.
// `runner`: the pilot's tolerance check runs samples again with its own.
std::optional<SampleRecord> run_sample(EnsembleRun& run, std::uint64_t k, std::vector<double>& trajectory,
                                       std::span<const double> uniforms = {},
                                       ensemble::SampleRunner* runner = nullptr) {
  ensemble::SampleRunner& by = runner ? *runner : run.runner;
  const auto start = std::chrono::steady_clock::now();
  const double start_cpu = thread_cpu_seconds();
  const double writing_before = run.sink->writing_seconds(), writing_cpu_before = run.sink->writing_cpu_seconds();
  std::optional<SampleRecord> r;
  const auto between_outputs = [&run] {
    run.sink->poll();
    if (process::stop_signal() != 0) throw ensemble::SampleAbandoned{};
  };
  try {
    r = uniforms.empty() ? by.run(k, false, trajectory, between_outputs)
                         : by.run_at(k, uniforms, trajectory, between_outputs);
  } catch (const ensemble::SampleAbandoned&) {
  } catch (const std::bad_alloc&) {
    throw;  // not the sample's failure: the rank's (exit 6)
  } catch (const std::exception& e) {
    r = by.failed_record(k, SampleStatus::integration_failed, std::string("internal error: ") + e.what());
  }
  run.busy_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() -
                      (run.sink->writing_seconds() - writing_before);
  run.busy_cpu_seconds += thread_cpu_seconds() - start_cpu - (run.sink->writing_cpu_seconds() - writing_cpu_before);
  if (r && !runner) ++run.samples_run;
  return r;
}

// The pilot's responses, and its first kToleranceReruns samples' again at
// tolerances kToleranceFactor times the job's, for the tolerance check
// (statistics/tolerance_check.hpp). Each rank fills the rows of the samples
// it ran and leaves the others 0: a sum over the ranks then puts every row
// together exactly (x + 0 = x, NaN and infinities included), in index order
// whoever ran what.
class PilotCheck {
 public:
  PilotCheck(const EnsembleRun& run, std::uint64_t pilot_end)
      : responses_(run.spec.responses.size()),
        reruns_(responses_ > 0 ? std::min(statistics::kToleranceReruns, pilot_end) : 0),
        tight_job_(run.job),
        pilot_(pilot_end * responses_, 0.0),
        rerun_(reruns_ * responses_, 0.0) {
    tight_job_.request.settings.relative_tolerance *= statistics::kToleranceFactor;
    tight_job_.request.settings.absolute_tolerance *= statistics::kToleranceFactor;
    if (reruns_ > 0) tight_.emplace(tight_job_, run.spec);
  }

  // Sample k's record, and its rerun when it is one of the first. False
  // when a stop signal abandoned the rerun.
  bool add(EnsembleRun& run, const SampleRecord& r) {
    std::copy(r.responses.begin(), r.responses.end(),
              pilot_.begin() + static_cast<std::ptrdiff_t>(r.index * responses_));
    if (r.index >= reruns_) return true;
    std::vector<double> trajectory;
    const std::optional<SampleRecord> again = run_sample(run, r.index, trajectory, {}, &*tight_);
    if (!again) return false;
    std::copy(again->responses.begin(), again->responses.end(),
              rerun_.begin() + static_cast<std::ptrdiff_t>(r.index * responses_));
    return true;
  }

  // Collective: every rank's rows together, then the check.
  statistics::ToleranceCheck finish(MPI_Comm comm) {
    all_reduce(comm, pilot_, MPI_SUM);
    all_reduce(comm, rerun_, MPI_SUM);
    const IntegratorSettings& settings = tight_job_.request.settings;
    return statistics::check_tolerances(settings.relative_tolerance / statistics::kToleranceFactor,
                                        settings.absolute_tolerance / statistics::kToleranceFactor, responses_, pilot_,
                                        rerun_);
  }

 private:
  std::size_t responses_;
  std::uint64_t reruns_;
  Job tight_job_;
  std::optional<ensemble::SampleRunner> tight_;
  std::vector<double> pilot_, rerun_;
};

// Collective: rank 0 says, once the pilot is done, how many ranks this job
// can keep busy before rank 0 limits it (ensemble/capacity.hpp), and warns
// when this run has more.
// The median of the pilot samples' CPU times: the first samples of each rank
// run slower (first touches of memory), and would inflate a mean.
void report_capacity(EnsembleRun& run, std::vector<double> pilot_cpu, double record_bytes) {
  std::vector<double> largest{record_bytes};
  all_reduce(run.comm, pilot_cpu, MPI_SUM);  // each sample's slot filled by the rank that ran it
  all_reduce(run.comm, largest, MPI_MAX);
  if (run.rank != 0 || run.options.quiet || pilot_cpu.empty()) return;
  std::nth_element(pilot_cpu.begin(), pilot_cpu.begin() + static_cast<std::ptrdiff_t>(pilot_cpu.size() / 2),
                   pilot_cpu.end());
  ensemble::Capacity c;
  c.record_bytes = static_cast<std::size_t>(largest[0]);
  c.record_seconds = ensemble::rank_zero_seconds_per_record(c.record_bytes);
  ensemble::count_rows(c, ensemble::SampleRows(run.spec, run.runner.layout(), run.runner.final_state_size()));
  ensemble::measure_writing(c, process::directory_of(run.options.output_path));
  c.sample_seconds = pilot_cpu[pilot_cpu.size() / 2];
  ensemble::print_capacity(std::cerr, c, run.spec, "the pilot's");
  if (static_cast<double>(run.size) > c.ranks(run.unit_rows))
    std::cerr << "warning: this run has " << run.size
              << " ranks: rank 0 will limit it (fewer ranks would do as well)\n";
}

// Rank 0: a response whose integration error is too large for it, said at
// once (the run goes on; the summary and the page say it again).
void warn_too_loose(const EnsembleRun& run, const statistics::ToleranceCheck& check) {
  for (std::size_t r = 0; r < check.change.size(); ++r)
    if (statistics::tolerance_verdict(check, r).kind == statistics::ToleranceVerdict::Kind::too_loose)
      std::cerr << "warning: the integration is " << statistics::describe_verdict(check, r) << " (response "
                << run.spec.responses[r].name << ", pilot samples 0-" << check.samples.back() << " rerun)\n";
}

// Into this rank's results (the statistics' update) and checkpoint, and on
// to rank 0. Counted as busy: it is the sample's own work, not waiting.
void keep(EnsembleRun& run, SampleRecord record, std::vector<double>* trajectory) {
  const auto start = std::chrono::steady_clock::now();
  if (run.results.keep(record, trajectory)) {
    run.sink->add(std::move(record));
    ++run.kept;
  }
  run.busy_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void hold_if_asked(EnsembleRun& run);

// A run after the pilot: kept (into the statistics when `trajectory` is
// given: its storage is taken, storage of the same size given back),
// counted, and the test hold honoured.
void keep_after_pilot(EnsembleRun& run, SampleRecord record, std::vector<double>* trajectory) {
  keep(run, std::move(record), trajectory);
  ++run.kept_after_pilot;
  hold_if_asked(run);
}

// --test-hold-after (test_hooks.hpp): once this rank has kept that many
// samples after the pilot, it says so in a file and waits for a stop signal.
void hold_if_asked(EnsembleRun& run) {
  const TestHooks& test = run.options.test;
  if (!test.hold_after || run.kept_after_pilot != *test.hold_after) return;
  if (!test.hold_unsaved) run.results.save();
  // Released by a stop signal; a rank whose launcher died (reparented) ends
  // as an unheld one would at its next MPI call. The launcher is read before
  // the file says "held": a test may kill it the moment the file appears,
  // and read after, it would already be the new parent, and the rank would
  // hold for ever (seen once under Open MPI 5 on a loaded machine).
  const pid_t launcher = ::getppid();
  process::write_file_atomically(run.checkpoint_dir / ("held-rank" + std::to_string(run.rank)),
                                 "pid " + std::to_string(::getpid()) + " kept " + std::to_string(run.kept) + "\n");
  while (process::stop_signal() == 0) {
    if (::getppid() != launcher) std::_Exit(kExitInternal);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

// The next sample of a block, or false when this rank must stop (a signal
// here, or another rank's flag in the queue).
bool may_go_on(WorkQueue& queue) {
  if (process::stop_signal() != 0) queue.interrupt();
  return !queue.interrupted();
}

// The statistics, allocated on every rank at once: when one rank cannot, all
// agree and stop (exit 6) instead of leaving the others in a collective.
// `kept`: the pilot's own trajectories of this rank. Throws
// OutOfMemoryEverywhere (caught in run_ensemble) on every rank when any failed.
bool start_statistics(EnsembleRun& run, statistics::Calibration calibration,
                      const std::vector<std::vector<double>>& kept = {}) {
  bool failed = false;
  try {
    statistics::EnsembleStatistics stats(run.runner.times(), run.runner.layout().columns, run.spec.histogram_bins,
                                         std::move(calibration));
    for (const auto& trajectory : kept) stats.add_sample(trajectory);
    run.results.start_statistics(std::move(stats));
  } catch (const std::bad_alloc&) {
    failed = true;
  }
  if (any_rank(run.comm, failed)) throw OutOfMemoryEverywhere{};
  return true;
}

// The pilot wave, samples 0 .. pilot_end-1 (every part runs them all, so
// that every part calibrates alike, but keeps only those of its range): the
// all-reduced minima and maxima of their deviations from the nominal run fix
// the calibration; then their trajectories count. False when interrupted.
bool run_pilot_wave(EnsembleRun& run, std::uint64_t pilot_end) {
  const std::size_t entries = run.nominal.size();
  std::vector<double> low(entries, std::numeric_limits<double>::infinity());
  std::vector<double> high(entries, -std::numeric_limits<double>::infinity());
  std::vector<std::vector<double>> kept;
  PilotCheck check(run, pilot_end);
  std::vector<double> pilot_cpu(pilot_end, 0.0);  // each sample's CPU, for rank 0's capacity
  double record_bytes = 0.0;
  {
    WorkQueue queue(run.comm, 0, pilot_end, run.spec.block_size);
    std::uint64_t begin = 0, end = 0;
    std::vector<double> trajectory;
    while (queue.next(begin, end)) {
      for (std::uint64_t k = begin; k < end && may_go_on(queue); ++k) {
        const double busy_before = run.busy_cpu_seconds;
        std::optional<SampleRecord> r = run_sample(run, k, trajectory);
        pilot_cpu[k] = run.busy_cpu_seconds - busy_before;
        if (r && record_bytes == 0.0) record_bytes = static_cast<double>(ensemble::typical_record_bytes(*r));
        if (!r || !check.add(run, *r)) break;
        const bool ok = r->status == SampleStatus::ok;
        for (std::size_t e = 0; ok && e < entries; ++e) {
          low[e] = std::min(low[e], trajectory[e] - run.nominal[e]);
          high[e] = std::max(high[e], trajectory[e] - run.nominal[e]);
        }
        if (!run.owns(k)) continue;
        keep(run, std::move(*r), nullptr);
        if (ok) kept.push_back(std::move(trajectory));
      }
      run.sink->end_block();
    }
    run.sink->end_wave();
    if (any_rank(run.comm, !may_go_on(queue))) return false;
  }
  all_reduce(run.comm, low, MPI_MIN);
  all_reduce(run.comm, high, MPI_MAX);
  run.tolerance = check.finish(run.comm);
  if (run.rank == 0 && !run.options.quiet) warn_too_loose(run, run.tolerance);
  report_capacity(run, pilot_cpu, record_bytes);
  const std::size_t columns = run.runner.layout().columns;
  return start_statistics(run,
                          statistics::calibrate(run.nominal, low, high, statistics::column_scales(run.nominal, columns),
                                                columns, run.spec.histogram_bins),
                          kept);
}

// Rank 0 writes common.state once the calibration is known; without it no
// part could ever be loaded, so a failure turns checkpoints off everywhere.
void save_common(EnsembleRun& run) {
  int written = 1;
  if (run.rank == 0 && run.results.checkpointing()) {
    try {
      persistence::write_checkpoint_common(run.checkpoint_dir, run.id, run.nominal,
                                           run.results.statistics().calibration(), run.tolerance);
    } catch (const process::FileError& e) {
      std::cerr << "warning: " << e.what() << "; the run goes on without checkpoints\n";
      written = 0;
    }
  }
  if (broadcast(run.comm, written) == 0) {
    run.results.drop_checkpoint();
    run.checkpoints = false;
  }
  run.results.save_if_due();  // the pilot may have taken longer than the interval
}

// Whether [begin, end) is a unit this rank runs (ensemble/capacity.hpp):
// a whole chunk of rows, none of them finished (a resumed run's) or stored
// with its trajectory. Rank 0 writes its own records itself.
bool whole_unit(const EnsembleRun& run, std::uint64_t begin, std::uint64_t end) {
  if (run.unit_rows == 0 || run.rank == 0 || end - begin != run.unit_rows || begin % run.unit_rows != 0 ||
      begin < run.spec.store_trajectories)
    return false;
  for (std::uint64_t k = begin; k < end; ++k)
    if (run.finished.contains(k)) return false;
  return true;
}

// Samples [from, to) of a wave, from the shared queue in blocks (units,
// aligned to their rows, when the run has them), skipping those a resumed
// run has. Returns whether a stop cut it short.
bool run_wave(EnsembleRun& run, std::uint64_t from, std::uint64_t to) {
  const std::uint64_t unit = run.unit_rows, block = run.spec.block_size;
  WorkQueue queue(run.comm, unit > 0 ? from / unit * unit : from, to, unit > 0 ? unit : block);
  std::uint64_t begin = 0, end = 0;
  std::vector<double> trajectory;
  bool stopped = false;
  while (!stopped && queue.next(begin, end)) {
    begin = std::max(begin, from);
    const bool whole = whole_unit(run, begin, end);
    if (whole) run.sink->begin_unit(begin, end - begin);
    for (std::uint64_t k = begin; k < end && !stopped; ++k) {
      stopped = !may_go_on(queue);
      if (stopped || run.finished.contains(k)) continue;
      std::optional<SampleRecord> r = run_sample(run, k, trajectory);
      if (r)
        keep_after_pilot(run, std::move(*r), &trajectory);
      else
        stopped = true;
      // Records of a block that is not a unit go every `block` samples, as
      // with blocks of that size (their memory, stored trajectories).
      if (!stopped && (k + 1 - begin) % block == 0) {
        if (!whole) run.sink->end_block();
        run.results.save_if_due();
      }
    }
    // A stop may come while a sample is kept (RankResults::keep refuses it):
    // the signal says so.
    if (whole) run.sink->end_unit(stopped || process::stop_signal() != 0);
    run.sink->end_block();
    if (!stopped) run.results.save_if_due();
  }
  const bool interrupted = !may_go_on(queue);
  run.sink->end_wave();
  return interrupted;
}

// Thrown out of a chain's response when this rank must stop (a signal, or
// another rank's flag): the chain is left where it is; a resumed run runs
// it again from its seed.
struct ChainStopped {};

// Chain c of a wave of chains (ensemble/wave_plan.hpp): each of its runs
// run here, in order. A run a resumed run already has is run again (the
// chain needs it to go on; the same bits) but not kept twice.
void run_chain(EnsembleRun& run, WorkQueue& queue, const ensemble::ChainWave& chains, std::uint64_t c,
               std::vector<double>& trajectory) {
  chains.run(c, [&](std::uint64_t k, std::span<const double> u) {
    if (!may_go_on(queue)) throw ChainStopped{};
    std::optional<SampleRecord> r = run_sample(run, k, trajectory, u);
    if (!r) throw ChainStopped{};
    const double value = chains.value(*r);
    if (!run.finished.contains(k))
      keep_after_pilot(run, std::move(*r), nullptr);  // not into /stats: the chains' runs are not draws
    return value;
  });
}

// A wave of chains: the queue hands out whole chains. Returns whether a
// stop cut it short.
bool run_chain_wave(EnsembleRun& run, const ensemble::Wave& wave) {
  const std::unique_ptr<const ensemble::ChainWave> chains = run.plan->chains(wave);
  WorkQueue queue(run.comm, wave.first, wave.end, wave.chain_length);
  std::uint64_t begin = 0, end = 0;
  std::vector<double> trajectory;
  bool stopped = false;
  while (!stopped && queue.next(begin, end)) {
    // A chain a resumed run has whole is not run again: rank 0 replays it
    // from the restored records. One cut short runs again from its seed.
    bool finished = true;
    for (std::uint64_t k = begin; k < end && finished; ++k) finished = run.finished.contains(k);
    if (finished) continue;
    try {
      run_chain(run, queue, *chains, (begin - wave.first) / wave.chain_length, trajectory);
    } catch (const ChainStopped&) {
      stopped = true;
    }
    run.sink->end_block();
    if (!stopped) run.results.save_if_due();
  }
  const bool interrupted = !may_go_on(queue);
  run.sink->end_wave();
  return interrupted;
}

// Rank 0 decides the next wave from every record so far; everyone gets it.
std::optional<ensemble::Wave> next_wave(EnsembleRun& run, const ensemble::Wave& done) {
  std::optional<ensemble::Wave> next;
  if (run.rank == 0) next = run.plan->next_wave(done, run.table ? &*run.table : nullptr);
  if (broadcast(run.comm, next ? 1 : 0) == 0) return std::nullopt;
  if (run.rank != 0) next.emplace();
  next->first = broadcast(run.comm, next->first);
  next->end = broadcast(run.comm, next->end);
  next->chain_length = broadcast(run.comm, next->chain_length);
  broadcast(run.comm, next->start);
  std::vector<char> name(next->name.begin(), next->name.end());
  broadcast(run.comm, name);
  next->name.assign(name.begin(), name.end());
  return next;
}

}  // namespace

int run_nominal(EnsembleRun& run) {
  const int code = on_rank_zero(run, [&run] {
    if (!run.options.part())
      run.writer = std::make_unique<h5::EnsembleWriter>(run.options.output_path, run.job, run.spec, run.runner.layout(),
                                                        run.runner.final_state_size(), run.unit_rows);
    if (run.restored) {
      run.nominal = run.restored->nominal;
      return kExitOk;
    }
    SampleRecord r;
    try {
      r = run.runner.run(0, true, run.nominal, [] {
        if (process::stop_signal() != 0) throw ensemble::SampleAbandoned{};
      });
    } catch (const ensemble::SampleAbandoned&) {
      std::cerr << "interrupted by " << process::signal_name(process::stop_signal())
                << " during the nominal run: nothing to resume yet; run it again\n";
      return kExitInterrupted;
    }
    if (r.status == SampleStatus::ok) return kExitOk;
    std::cerr << run.job.file << ": the nominal run failed: " << r.reason << "\n";
    return kExitIntegration;
  });
  if (code != kExitOk) return code;
  broadcast(run.comm, run.nominal);
  return kExitOk;
}

int run_waves(EnsembleRun& run) {
  ensemble::Wave wave = run.plan->first_wave();
  std::uint64_t from = wave.first;
  if (run.restored) {
    start_statistics(run, run.restored->calibration);
  } else {
    const std::uint64_t pilot_end = std::min(run.spec.pilot_samples, wave.end);
    if (!run_pilot_wave(run, pilot_end)) return stop_interrupted(run, false);
    save_common(run);
    hold_if_asked(run);
    from = pilot_end;
  }
  for (;;) {
    if (run.rank == 0 && designs::rules_of(run.spec.design).adaptive(run.spec)) run.progress->wave(wave.end, wave.name);
    const std::uint64_t first = std::max({wave.first, from, run.first});
    const bool interrupted = wave.chain_length > 0 ? run_chain_wave(run, wave)
                                                   : run_wave(run, first, std::max(first, std::min(wave.end, run.end)));
    if (any_rank(run.comm, interrupted)) return stop_interrupted(run, true);
    const std::optional<ensemble::Wave> next = next_wave(run, wave);
    if (!next) {
      run.samples_used = std::min(wave.end, run.end);
      return kExitOk;
    }
    wave = *next;
    from = wave.first;
  }
}

namespace {

// The clean stop's line, also as DIR/stopped: a launcher that ends the job
// itself (mpirun on Ctrl-C, SIGTERM; Open MPI 5's in every case) exits 1
// and may not pass the line on, so a batch script tells a clean stop by this
// file (jobs/slurm_ensemble.sh). Written before the line is printed; a run
// that starts on the checkpoint removes it (open_checkpoint).
void write_stopped_marker(const EnsembleRun& run, const std::string& line) {
  try {
    process::write_file_atomically(run.checkpoint_dir / "stopped", line);
  } catch (const process::FileError& e) {
    std::cerr << "warning: " << e.what() << " (the marker of a clean stop)\n";
  }
}

// Rank 0: the temporary output removed, and what a resume will find.
void report_interruption(EnsembleRun& run, bool resumable, bool all_saved, std::uint64_t kept, int signal_number) {
  run.records->finish_progress();
  run.writer.reset();  // removes the temporary output
  const std::string what = signal_number != 0 ? process::signal_name(signal_number) : "a signal";
  const std::string dir = run.checkpoint_dir.string();
  if (!resumable) {
    std::cerr << "interrupted by " << what << " during the pilot samples: nothing to resume yet; run it again\n";
    persistence::remove_checkpoint(dir);
  } else if (!run.checkpoints) {
    std::cerr << "interrupted by " << what << "; checkpoints are off (--checkpoint-every 0, or a checkpoint "
              << "could not be written), so this run's samples are not kept\n";
  } else if (!all_saved) {
    std::cerr << "interrupted by " << what << "; a rank could not write its checkpoint (see above): --resume "
              << "keeps what " << dir << " holds\n";
  } else {
    const std::string line = "interrupted by " + what + " after " + std::to_string(kept) + " of " +
                             std::to_string(run.end - run.first) + " samples; resume with --resume (checkpoint " + dir +
                             ")\n";
    write_stopped_marker(run, line);
    std::cerr << line;
  }
}

}  // namespace

int stop_interrupted(EnsembleRun& run, bool resumable) {
  const bool saved = resumable && run.results.save(Sync::no);  // the signal thread's save, or a cheap repeat
  const bool all_saved = !any_rank(run.comm, resumable && !saved);
  const std::uint64_t kept = sum_over_ranks(run.comm, saved ? run.results.saved_records() : 0) + run.restored_samples;
  const int signal_number = max_over_ranks(run.comm, process::stop_signal());
  if (run.rank == 0) report_interruption(run, resumable, all_saved, kept, signal_number);
  // The stop's save was not flushed (SIGKILL may be seconds away); with the
  // message out, it is flushed in place. A SIGKILL during this loses
  // nothing: what was written outlives the process in the page cache.
  if (saved) run.results.save(Sync::yes);
  return kExitInterrupted;
}

}  // namespace treedyn::parallel
