// The phases that set up where results go: the output path and the
// checkpoint (open_output, share_restored), the record transport and this
// rank's checkpoint (start_records).
#include <filesystem>
#include <iostream>

#include "common/exit_codes.hpp"
#include "hdf5/read_file.hpp"
#include "parallel/collectives.hpp"
#include "parallel/driver.hpp"
#include "persistence/part_file.hpp"
#include "process/atomic_file.hpp"

namespace treedyn::parallel {
namespace fs = std::filesystem;
namespace {

// The job text an existing output was made from: an ensemble file's root
// attribute, a part file's own; nullopt when it is neither.
std::optional<std::string> output_job_text(const EnsembleRun& run, const fs::path& out) {
  try {
    if (run.options.part()) {
      const persistence::PartFile part = persistence::read_part_file(out);
      if (part.first != run.first || part.end != run.end) return std::string();  // another range: another output
      return part.job_text;
    }
    const h5::ReadFile file(out);
    if (!file.has_attribute("/", "job_text") || !file.has_attribute("/", "samples_ok")) return std::nullopt;
    return file.string_attribute("/", "job_text");
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

void note_stale(const std::vector<std::string>& removed) {
  for (const std::string& f : removed)
    std::cerr << "note: removed " << f << ", a temporary file left by a process that no longer runs\n";
}

// Rank 0, --resume without a checkpoint: an output already there is this
// job's finished run (kAlreadyDone: nothing to do, never a recompute over
// it), or another job's (refused), or none (kExitOk: start).
int finished_output(EnsembleRun& run) {
  const fs::path& out = run.options.output_path;
  if (!fs::exists(out)) return kExitOk;
  const std::optional<std::string> job = output_job_text(run, out);
  if (job && *job == run.job.text) {
    std::cerr << "note: " << out.string() << " is this job's " << (run.options.part() ? "part" : "ensemble")
              << ", complete, and there is no checkpoint to resume: nothing to do (remove it to run the job "
                 "again)\n";
    return kAlreadyDone;
  }
  std::cerr << "error: " << out.string() << " is "
            << (job ? "another job's output (its job text differs)"
                    : "not "
                      "an output of treedyn-ensemble")
            << ": give this run another -o, or remove it to run the job into it\n";
  return kExitBadInput;
}

// Rank 0: load the checkpoint (--resume), or refuse to start over one, or
// create an empty directory for this run's. Returns an exit code.
int open_checkpoint(EnsembleRun& run) {
  const fs::path& dir = run.checkpoint_dir;
  std::error_code ignored;
  fs::remove(dir / "stopped", ignored);  // an earlier stop's marker: this run is not stopped (yet)
  if (run.options.resume) {
    run.restored = persistence::load_checkpoint(dir, run.id, ensemble::statistics_shape(run.runner),
                                                ensemble::record_shape(run.runner, run.first, run.end));
    if (!run.restored) {
      if (const int code = finished_output(run); code != kExitOk) return code;
      std::cerr << "note: no checkpoint " << dir.string() << " to resume (or it was written before the pilot "
                << "samples were done): starting from the beginning\n";
    }
  } else if (persistence::checkpoint_exists(dir)) {
    std::cerr << "error: " << dir.string() << " holds the checkpoint of an earlier run of this output: "
              << "resume it with --resume, or remove that directory to start afresh\n";
    return kExitBadInput;
  }
  if (run.restored || run.options.checkpoint_every <= 0.0) return kExitOk;
  persistence::remove_checkpoint(dir);
  try {
    persistence::create_checkpoint_directory(dir);
    return kExitOk;
  } catch (const process::FileError& e) {
    std::cerr << "error: " << e.what() << " (or turn checkpoints off with --checkpoint-every 0)\n";
    return kExitIo;
  }
}

}  // namespace

int open_output(EnsembleRun& run) {
  return on_rank_zero(run, [&run] {
    process::check_output_path(run.options.output_path);
    try {
      run.lock.emplace(run.options.output_path, run.options.provenance.command_line);
    } catch (const process::OutputLocked& e) {
      std::cerr << "error: " << e.what() << "\n";
      return static_cast<int>(kExitBadInput);
    }
    const fs::path output(run.options.output_path);
    note_stale(process::remove_stale_temporaries(output.parent_path(), output.filename().string()));
    if (fs::is_directory(run.checkpoint_dir)) note_stale(process::remove_stale_temporaries(run.checkpoint_dir, ""));
    return open_checkpoint(run);
  });
}

int share_restored(EnsembleRun& run) {
  if (broadcast(run.comm, run.rank == 0 && run.restored ? 1 : 0) == 0) return kExitOk;
  if (run.rank != 0) run.restored.emplace();
  std::vector<char> calibration;
  ByteWriter out(calibration);
  std::vector<std::uint64_t> finished;
  if (run.rank == 0) {
    run.restored->calibration.write(out);
    for (const auto& [first, end] : run.restored->finished) run.finished.append(first, end);
    for (const auto& [first, end] : run.finished.ranges()) finished.insert(finished.end(), {first, end});
  }
  broadcast(run.comm, calibration);
  broadcast(run.comm, finished);
  if (run.rank != 0) {
    ByteReader in(calibration, "the restored calibration");
    run.restored->calibration = statistics::Calibration::read(in, run.runner.times() * run.runner.layout().columns);
    for (std::size_t k = 0; k + 1 < finished.size(); k += 2) run.finished.append(finished[k], finished[k + 1]);
  }
  return kExitOk;
}

namespace {

// Rank 0, resuming: the restored statistics stay apart until the end (so
// this run's checkpoints hold only this run's samples), the records go to
// the writer, and everything restored becomes the base of a new generation.
int restore_on_rank_zero(EnsembleRun& run) {
  run.restored_samples = run.restored->records.size();
  run.generation = persistence::consolidate_checkpoint(run.checkpoint_dir, run.id, *run.restored);
  run.restored_statistics = std::move(run.restored->statistics);
  run.tolerance = run.restored->tolerance;
  run.restored->statistics.reset();
  std::cerr << "resuming: " << run.restored_samples << " of " << run.end - run.first << " samples from "
            << run.checkpoint_dir.string() << "\n";
  run.records->restore(std::move(run.restored->records));
  return kExitOk;
}

}  // namespace

int start_records(EnsembleRun& run) {
  run.progress = std::make_unique<ensemble::Progress>(run.end - run.first, run.options.progress_interval,
                                                      run.rank == 0 && !run.options.quiet);
  if (run.rank == 0 && !run.spec.responses.empty() && !run.options.part())
    run.table.emplace(run.spec.runs, run.spec.input_dimensions(), run.spec.responses.size());
  if (run.rank == 0) {
    auto writer = std::make_unique<RecordWriter>(run.comm, run.size, run.writer.get(), *run.progress,
                                                 run.table ? &*run.table : nullptr,
                                                 run.options.part() ? &run.part_records : nullptr);
    run.records = writer.get();
    run.sink = std::move(writer);
  } else {
    std::optional<ensemble::SampleRows> rows;
    if (run.unit_rows > 0) rows.emplace(run.spec, run.runner.layout(), run.runner.final_state_size());
    run.sink = std::make_unique<RecordSender>(run.comm, run.size, std::move(rows));
  }
  if (run.restored) {
    if (const int code = on_rank_zero(run, [&run] { return restore_on_rank_zero(run); }); code != kExitOk) return code;
    run.generation = broadcast(run.comm, run.generation);
    run.restored_samples = sum_over_ranks(run.comm, run.restored_samples);
    run.progress->restored(run.restored_samples);
  }
  run.checkpoints = run.options.checkpoint_every > 0.0;
  if (run.checkpoints)
    run.results.use_checkpoint(std::make_unique<persistence::RankCheckpoint>(run.checkpoint_dir, run.id, run.generation,
                                                                             "rank" + std::to_string(run.rank)),
                               run.options.checkpoint_every);
  return kExitOk;
}

}  // namespace treedyn::parallel
