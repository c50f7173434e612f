#include "app/merge_parts.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <iostream>
#include <numeric>
#include <optional>

#include "common/exit_codes.hpp"
#include "ensemble/index_ranges.hpp"
#include "ensemble/sample_runner.hpp"
#include "hdf5/ensemble_file.hpp"
#include "job/job_error.hpp"
#include "job/sample_job.hpp"
#include "persistence/part_file.hpp"
#include "process/atomic_file.hpp"
#include "process/output_lock.hpp"

namespace treedyn {
namespace {

// A refusal: the message is printed, the merge exits 2.
struct Refused {
  std::string what;
};

std::string range_text(std::uint64_t first, std::uint64_t end) {
  return std::to_string(first) + " .. " + std::to_string(end - 1);
}

// Every part, of the same job and build as the first, and of this build.
std::vector<persistence::PartFile> read_parts(const std::vector<std::string>& names) {
  std::vector<persistence::PartFile> parts;
  for (const std::string& name : names) {
    try {
      parts.push_back(persistence::read_part_file(name));
    } catch (const persistence::CheckpointError& e) {
      throw Refused{std::string(e.what()) + "; run that part again with its --samples range (into `" + name +
                    "`) and merge again: the other parts are kept"};
    } catch (const process::FileError& e) {
      throw Refused{e.what()};
    }
    const persistence::PartFile& p = parts.back();
    if (p.id.build != h5::build_identity())
      throw Refused{name + " was written by another build (" + p.id.build + "; this is " + h5::build_identity() +
                    "): merge with the build that ran the parts"};
    if (p.id.job_hash != parts[0].id.job_hash)
      throw Refused{name + " comes from another job file than " + names[0] + " (job text hash " + p.id.job_hash +
                    " against " + parts[0].id.job_hash + ")"};
  }
  return parts;
}

// The samples the parts hold, which must not overlap.
ensemble::IndexRanges held_samples(const std::vector<persistence::PartFile>& parts,
                                   const std::vector<std::string>& names) {
  std::vector<std::size_t> order(parts.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return parts[a].first < parts[b].first; });
  ensemble::IndexRanges held;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const persistence::PartFile& b = parts[order[k]];
    if (k > 0 && b.first < parts[order[k - 1]].end)
      throw Refused{names[order[k]] + " holds samples " + range_text(b.first, b.end) + ", which overlap the samples " +
                    range_text(parts[order[k - 1]].first, parts[order[k - 1]].end) + " of " + names[order[k - 1]]};
    held.append(b.first, b.end);
  }
  return held;
}

// Each part fits the job it carries, and all calibrated alike (the pilot
// samples are fixed indices, so they must have).
void check_fit(const std::vector<persistence::PartFile>& parts, const std::vector<std::string>& names,
               const EnsembleSpec& spec, const ensemble::SampleRunner& runner) {
  const std::size_t entries = runner.times() * runner.layout().columns;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    if (parts[k].nominal.size() != entries || parts[k].end > spec.runs || parts[k].nominal != parts[0].nominal)
      throw Refused{names[k] + " does not fit the job it carries (nominal run, histogram or range)"};
    if (!(parts[k].calibration == parts[0].calibration))
      throw Refused{"the parts' calibrations differ: they did not run the same pilot samples"};
    try {
      persistence::check_records(parts[k].records, ensemble::record_shape(runner, parts[k].first, parts[k].end),
                                 "part file " + names[k]);
    } catch (const persistence::CheckpointError& e) {
      throw Refused{e.what()};
    }
  }
}

// The union of the parts' records, by index; samples no part holds get
// status 3 (not run).
std::vector<SampleRecord> merged_records(std::vector<persistence::PartFile>& parts, const ensemble::IndexRanges& held,
                                         const ensemble::SampleRunner& runner, std::uint64_t samples) {
  std::vector<SampleRecord> records;
  for (persistence::PartFile& part : parts)
    for (SampleRecord& r : part.records) records.push_back(std::move(r));
  for (std::uint64_t k = 0; k < samples && held.count() < samples; ++k)
    if (!held.contains(k)) records.push_back(runner.failed_record(k, SampleStatus::not_run, "not in the merged parts"));
  std::sort(records.begin(), records.end(), [](const auto& a, const auto& b) { return a.index < b.index; });
  return records;
}

void note_incomplete(const ensemble::IndexRanges& held, std::uint64_t samples) {
  std::cerr << "note: the parts hold " << held.count() << " of " << samples << " samples (";
  for (std::size_t k = 0; k < held.ranges().size(); ++k)
    std::cerr << (k ? ", " : "") << range_text(held.ranges()[k].first, held.ranges()[k].second);
  std::cerr << "); the others are written with status 3 (not run), and /responses and /sensitivity, which "
               "need every sample, are left out\n";
}

// One process did the merge; the parts' own runs are described by them.
ensemble::RunSummary merge_summary(const std::vector<SampleRecord>& records) {
  ensemble::RunSummary summary;
  for (const SampleRecord& r : records) {
    if (r.status == SampleStatus::ok)
      ++summary.ok;
    else if (r.status != SampleStatus::not_run)
      ++summary.failed;
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  summary.peak_rss_mib = {static_cast<double>(usage.ru_maxrss) / 1024.0};
  summary.samples_per_rank = {0};
  summary.busy_seconds = {0.0};
  summary.busy_cpu_seconds = {0.0};
  summary.writing_cpu_seconds = {0.0};
  summary.cpu_seconds = {static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec)};
  return summary;
}

}  // namespace

int merge_parts(const std::vector<std::string>& names, const std::string& output_path, bool quiet,
                const h5::RunProvenance& run) {
  const auto start = std::chrono::steady_clock::now();
  try {
    process::check_output_path(output_path);
    const process::OutputLock lock(output_path, run.command_line);  // one output, one owner (a run's or a merge's)
    std::vector<persistence::PartFile> parts = read_parts(names);
    const ensemble::IndexRanges held = held_samples(parts, names);
    const auto [job, spec] = read_ensemble_job(JobDocument::parse(parts[0].job_text, parts[0].job_path));
    ensemble::SampleRunner runner(job, spec);
    check_fit(parts, names, spec, runner);
    const bool complete = held.count() == spec.runs;
    if (!complete) note_incomplete(held, spec.runs);
    statistics::EnsembleStatistics stats(runner.times(), runner.layout().columns, spec.histogram_bins,
                                         parts[0].calibration);
    for (std::size_t k = 0; k < parts.size(); ++k) stats.add_state(parts[k].statistics, "part file " + names[k]);
    std::vector<SampleRecord> records = merged_records(parts, held, runner, spec.runs);
    std::vector<analysis::ResponseAnswer> answers;
    if (complete && !spec.responses.empty()) {
      ensemble::ResponseTable table(spec.runs, spec.input_dimensions(), spec.responses.size());
      for (const SampleRecord& r : records) table.add(r);
      answers = analysis::answer_responses(spec, table);
    }
    ensemble::RunSummary summary = merge_summary(records);
    h5::RunProvenance provenance = run;
    provenance.job_path = parts[0].job_path;  // the job the parts ran (absolute), not a part file
    summary.samples_used = spec.runs;
    summary.stop_reason = complete ? "merged parts: every sample of the design was run"
                                   : "merged parts: " + std::to_string(held.count()) + " of the samples were run";
    h5::EnsembleWriter writer(output_path, job, spec, runner.layout(), runner.final_state_size());
    const auto writing = std::chrono::steady_clock::now();
    const std::clock_t writing_cpu = std::clock();
    writer.write_records(std::move(records));
    summary.writing_seconds = {std::chrono::duration<double>(std::chrono::steady_clock::now() - writing).count()};
    summary.writing_cpu_seconds = {static_cast<double>(std::clock() - writing_cpu) / CLOCKS_PER_SEC};
    writer.write_merge_origin(names, held.ranges());
    writer.complete(parts[0].nominal, stats, answers, parts[0].tolerance, std::move(summary), provenance, start);
    if (!quiet && !answers.empty()) analysis::print_response_summary(std::cout, spec, answers, parts[0].tolerance);
    std::printf("wrote %s (%llu of %llu samples from %zu parts)\n", output_path.c_str(),
                static_cast<unsigned long long>(held.count()), static_cast<unsigned long long>(spec.runs),
                parts.size());
    return kExitOk;
  } catch (const Refused& r) {
    std::cerr << "error: " << r.what << "\n";
  } catch (const process::OutputLocked& e) {
    std::cerr << "error: " << e.what() << "\n";
  } catch (const JobError& e) {
    std::cerr << "error: the job inside " << names[0] << ": " << e.what() << "\n";
  } catch (const DecodeError& e) {
    std::cerr << "error: " << e.what() << "\n";
  } catch (const process::FileError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitIo;
  }
  return kExitBadInput;
}

}  // namespace treedyn
