// The last phase: statistics summed onto rank 0, every rank's load and host
// gathered there, then the ensemble file (or a part's file), the summary and
// the checkpoint's removal.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "analysis/digest.hpp"
#include "common/exit_codes.hpp"
#include "designs/registry_analysis.hpp"
#include "parallel/collectives.hpp"
#include "parallel/driver.hpp"
#include "parallel/statistics_reduce.hpp"
#include "persistence/part_file.hpp"

namespace treedyn::parallel {
namespace {

// Every rank's peak memory, samples, busy time and time writing records, on
// rank 0.
ensemble::RunSummary gather_loads(const EnsembleRun& run) {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  constexpr int kLoads = 7;
  const double cpu = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                     1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
  const double mine[kLoads] = {static_cast<double>(usage.ru_maxrss) / 1024.0,
                               static_cast<double>(run.samples_run),
                               run.busy_seconds,
                               run.sink->writing_seconds(),
                               run.busy_cpu_seconds,
                               run.sink->writing_cpu_seconds(),
                               cpu};
  std::vector<double> all(kLoads * static_cast<std::size_t>(run.size));
  MPI_Gather(mine, kLoads, MPI_DOUBLE, all.data(), kLoads, MPI_DOUBLE, 0, run.comm);
  ensemble::RunSummary summary;
  summary.ranks = run.size;
  for (int r = 0; r < run.size && run.rank == 0; ++r) {
    const double* loads = all.data() + static_cast<std::size_t>(kLoads * r);
    summary.peak_rss_mib.push_back(loads[0]);
    summary.samples_per_rank.push_back(static_cast<long long>(loads[1]));
    summary.busy_seconds.push_back(loads[2]);
    summary.writing_seconds.push_back(loads[3]);
    summary.busy_cpu_seconds.push_back(loads[4]);
    summary.writing_cpu_seconds.push_back(loads[5]);
    summary.cpu_seconds.push_back(loads[6]);
  }
  return summary;
}

// Every rank's host name and the MPI library, for the file's provenance.
h5::RunProvenance gather_provenance(const EnsembleRun& run) {
  h5::RunProvenance provenance = run.options.provenance;
  char name[MPI_MAX_PROCESSOR_NAME] = {};
  int length = 0;
  MPI_Get_processor_name(name, &length);
  std::vector<char> all(static_cast<std::size_t>(run.size) * MPI_MAX_PROCESSOR_NAME, '\0');
  MPI_Gather(name, MPI_MAX_PROCESSOR_NAME, MPI_CHAR, all.data(), MPI_MAX_PROCESSOR_NAME, MPI_CHAR, 0, run.comm);
  provenance.ranks = run.size;
  for (int r = 0; r < run.size && run.rank == 0; ++r)
    provenance.rank_hosts.emplace_back(all.data() + static_cast<std::size_t>(r) * MPI_MAX_PROCESSOR_NAME);
  char library[MPI_MAX_LIBRARY_VERSION_STRING] = {};
  MPI_Get_library_version(library, &length);
  provenance.mpi_library = std::string(library, static_cast<std::size_t>(length));
  while (!provenance.mpi_library.empty() &&
         (provenance.mpi_library.back() == '\n' || provenance.mpi_library.back() == '\0'))
    provenance.mpi_library.pop_back();
  return provenance;
}

void note_stale_outputs(const EnsembleRun& run) {
  const std::filesystem::path output(run.options.output_path);
  for (const std::string& f : process::remove_stale_temporaries(output.parent_path(), output.filename().string()))
    std::cerr << "note: removed " << f << ", a temporary file left by a process that no longer runs\n";
}

// Rank 0, a part of a split ensemble: its records, statistics and
// calibration into the part file, atomically.
int write_part(EnsembleRun& run, const statistics::EnsembleStatistics& stats) {
  if (!run.records->io_error().empty()) {
    std::cerr << "error: " << run.records->io_error() << "\n";
    return kExitIo;
  }
  persistence::PartFile part;
  part.id = run.job_id;
  part.job_text = run.job.text;
  part.job_path = run.options.provenance.job_path.empty() ? run.options.job_path : run.options.provenance.job_path;
  part.first = run.first;
  part.end = run.end;
  part.nominal = run.nominal;
  part.calibration = stats.calibration();
  part.tolerance = run.tolerance;
  part.records = std::move(run.part_records);
  std::sort(part.records.begin(), part.records.end(), [](const auto& a, const auto& b) { return a.index < b.index; });
  try {
    persistence::write_part_file(run.options.output_path, part, stats);
  } catch (const process::FileError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitIo;
  }
  if (!run.options.quiet)
    std::cout << "part: samples " << run.first << " .. " << run.end - 1 << " of " << run.spec.runs << ", "
              << run.records->failed() << " failed\n";
  std::printf("wrote %s (merge the parts with: treedyn-ensemble merge -o OUT.h5 PART ...)\n",
              run.options.output_path.c_str());
  return kExitOk;
}

// Why the run ended where it did, for the file and the summary.
std::string stop_reason_of(const EnsembleRun& run, const designs::RunAnswer* answer) {
  if (answer) return answer->stop_reason();
  if (!run.spec.stop) return "no stopping rule: every sample of the design was run";
  if (run.table)
    if (auto reason = analysis::stop_reason(run.spec, *run.table, run.samples_used)) return *reason;
  return "no target of [ensemble.stop] held: stopped at the most samples, " + std::to_string(run.spec.runs);
}

// Rank 0, a whole ensemble: the records are in the file already (a write
// error among them is reported before anything else is written); the rest
// goes the same way as a merge's (EnsembleWriter::complete).
int write_ensemble(EnsembleRun& run, const statistics::EnsembleStatistics& stats, ensemble::RunSummary summary,
                   const h5::RunProvenance& provenance) {
  summary.failed = run.records->failed();
  summary.ok = run.records->done() - summary.failed;
  summary.samples_used = run.samples_used;
  summary.unit_rows = run.unit_rows;
  summary.samples_in_units = run.records->done_in_units();
  summary.unit_storing_cpu_seconds = run.records->unit_storing_cpu_seconds();
  if (run.samples_used < run.spec.runs && run.table) run.table->truncate(run.samples_used);
  // The design's answer for the whole run (subset simulation's levels), if any.
  const std::unique_ptr<const designs::RunAnswer> run_answer =
      run.table ? designs::run_answer(run.spec, *run.table) : nullptr;
  summary.stop_reason = stop_reason_of(run, run_answer.get());
  const std::vector<analysis::ResponseAnswer> answers =
      run.table ? analysis::answer_responses(run.spec, *run.table) : std::vector<analysis::ResponseAnswer>{};
  try {
    if (!run.records->io_error().empty()) throw process::FileError(run.records->io_error());
    if (run.samples_used < run.spec.runs) run.writer->keep_samples(run.samples_used);
    if (run_answer) run.writer->write_run_answer(*run_answer, run.samples_used);
    summary =
        run.writer->complete(run.nominal, stats, answers, run.tolerance, std::move(summary), provenance, run.start);
  } catch (const process::FileError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitIo;
  }
  if (!run.options.quiet) {
    analysis::print_digest(std::cout, analysis::digest_of(run.job, run.spec, stats, summary));
    analysis::print_response_summary(std::cout, run.spec, answers, run.tolerance);
    if (run_answer) run_answer->print(std::cout, run.spec);
    if (run.spec.stop)
      std::cout << "stopped after " << run.samples_used << " of at most " << run.spec.runs
                << " samples: " << summary.stop_reason << "\n";
  }
  std::printf("wrote %s\n", run.options.output_path.c_str());
  return kExitOk;
}

}  // namespace

int finish_run(EnsembleRun& run) {
  statistics::EnsembleStatistics stats = run.results.finish();  // the signal thread keeps off it from here on
  if (run.restored_statistics) stats.merge(*run.restored_statistics);
  reduce_statistics(run.comm, stats);
  if (run.rank == 0) {  // before the gather, so that its time is in rank 0's writing
    run.records->finish_progress();
    run.records->write_held();
  }
  const ensemble::RunSummary summary = gather_loads(run);
  const h5::RunProvenance provenance = gather_provenance(run);
  int code = kExitOk;
  if (run.rank == 0) {
    code = run.options.part() ? write_part(run, stats) : write_ensemble(run, stats, summary, provenance);
  }
  // Every rank's last save on the disk (the others' done while rank 0
  // wrote, as a rule) before rank 0 removes the checkpoint, or a failed
  // run's abandon() judges what it holds; rank 0's code reaches everyone.
  run.results.await_final_save();
  code = max_over_ranks(run.comm, code);
  if (run.rank == 0 && code == kExitOk) {
    persistence::remove_checkpoint(run.checkpoint_dir);
    note_stale_outputs(run);  // the processes of a run killed just before this one are gone by now
  }
  return code;
}

}  // namespace treedyn::parallel
