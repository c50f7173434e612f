#include "app/merge_parts.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <iostream>
#include <optional>

#include "app/exit_codes.hpp"
#include "ensemble/answers.hpp"
#include "ensemble/checkpoint.hpp"
#include "ensemble/digest.hpp"
#include "ensemble/ensemble_spec.hpp"
#include "ensemble/sample_job.hpp"
#include "ensemble/sample_runner.hpp"
#include "hdf5/ensemble_file.hpp"
#include "hdf5/hdf5.hpp"
#include "job/job_error.hpp"

namespace treedyn {
namespace {

using ensemble::PartFile;
using ensemble::SampleRecord;

std::string range_text(std::uint64_t first, std::uint64_t end) {
  return std::to_string(first) + " .. " + std::to_string(end - 1);
}

// Every part of the same job and build as the first, and of this build.
bool same_origin(const std::vector<PartFile>& parts, const std::vector<std::string>& names) {
  const std::string build = build_identity();
  for (std::size_t k = 0; k < parts.size(); ++k) {
    if (parts[k].id.build != build) {
      std::cerr << "error: " << names[k] << " was written by another build (" << parts[k].id.build
                << "; this is " << build << "): merge with the build that ran the parts\n";
      return false;
    }
    if (parts[k].id.job_hash != parts[0].id.job_hash) {
      std::cerr << "error: " << names[k] << " comes from another job file than " << names[0]
                << " (job text hash " << parts[k].id.job_hash << " against " << parts[0].id.job_hash << ")\n";
      return false;
    }
  }
  return true;
}

}  // namespace

int merge_parts(const std::vector<std::string>& names, const std::string& output_path, bool quiet,
                const RunProvenance& run) {
  std::vector<PartFile> parts;
  try {
    for (const std::string& name : names) parts.push_back(ensemble::read_part_file(name));
  } catch (const ensemble::CheckpointError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitBadInput;
  }
  if (!same_origin(parts, names)) return kExitBadInput;

  // Disjoint ranges, in order.
  std::vector<std::size_t> order(parts.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return parts[a].first < parts[b].first; });
  for (std::size_t k = 1; k < order.size(); ++k) {
    const PartFile& a = parts[order[k - 1]];
    const PartFile& b = parts[order[k]];
    if (b.first < a.end) {
      std::cerr << "error: " << names[order[k]] << " holds samples " << range_text(b.first, b.end)
                << ", which overlap the samples " << range_text(a.first, a.end) << " of " << names[order[k - 1]]
                << "\n";
      return kExitBadInput;
    }
  }

  Job job;
  ensemble::EnsembleSpec spec;
  try {
    job = parse_job(parts[0].job_text, parts[0].job_path);
    ensemble::apply_sample_section(job);
    spec = ensemble::read_ensemble(job);
  } catch (const JobError& e) {
    std::cerr << "error: the job inside " << names[0] << ": " << e.what() << "\n";
    return kExitBadInput;
  }
  ensemble::SampleRunner runner(job, spec);
  const std::size_t entries = runner.times() * runner.layout().columns;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    if (parts[k].nominal.size() != entries || parts[k].bins != spec.histogram_bins ||
        parts[k].end > spec.samples || parts[k].nominal != parts[0].nominal) {
      std::cerr << "error: " << names[k] << " does not fit the job it carries (nominal run, histogram or range)\n";
      return kExitBadInput;
    }
    ensemble::RecordShape shape;
    shape.first = parts[k].first;
    shape.end = parts[k].end;
    shape.inputs = spec.input_dimensions();
    shape.reductions = spec.per_sample.size() * runner.layout().columns;
    shape.responses = spec.responses.size();
    shape.final_state = runner.final_state_size();
    shape.trajectory = entries;
    shape.stored = spec.store_trajectories;
    try {
      ensemble::check_records(parts[k].records, shape, "part file " + names[k]);
    } catch (const ensemble::CheckpointError& e) {
      std::cerr << "error: " << e.what() << "\n";
      return kExitBadInput;
    }
  }

  // The held ranges (adjacent parts joined) and the gaps.
  std::vector<std::pair<std::uint64_t, std::uint64_t>> held;
  for (std::size_t k : order) {
    if (parts[k].first == parts[k].end) continue;
    if (!held.empty() && held.back().second == parts[k].first)
      held.back().second = parts[k].end;
    else
      held.emplace_back(parts[k].first, parts[k].end);
  }
  std::uint64_t holding = 0;
  for (const auto& [a, b] : held) holding += b - a;
  const bool complete = holding == spec.samples;
  if (!complete) {
    std::cerr << "note: the parts hold " << holding << " of " << spec.samples << " samples (";
    for (std::size_t k = 0; k < held.size(); ++k) std::cerr << (k ? ", " : "") << range_text(held[k].first, held[k].second);
    std::cerr << "); the others are written with status 3 (not run), and /responses and /sensitivity, which "
                 "need every sample, are left out\n";
  }

  ensemble::EnsembleStatistics stats(runner.times(), runner.layout().columns, spec.histogram_bins,
                                     parts[0].calibration);
  std::vector<SampleRecord> records;
  std::optional<ensemble::ResponseTable> table;
  if (complete && !spec.responses.empty()) table.emplace(spec.samples, spec.input_dimensions(), spec.responses.size());
  EnsembleSummary summary;
  for (PartFile& part : parts) {
    // Each part's calibration is the same (fixed pilot indices); check it.
    const ensemble::Calibration& c = part.calibration;
    const ensemble::Calibration& c0 = parts[0].calibration;
    if (c.center != c0.center || c.scale != c0.scale || c.low != c0.low || c.width != c0.width) {
      std::cerr << "error: the parts' calibrations differ: they did not run the same pilot samples\n";
      return kExitBadInput;
    }
    ensemble::restore_statistics(part.statistics, stats);
    for (SampleRecord& r : part.records) {
      if (table) table->add(r);
      if (r.status == ensemble::SampleStatus::ok) ++summary.ok;
      else ++summary.failed;
      records.push_back(std::move(r));
    }
  }
  std::sort(records.begin(), records.end(), [](const SampleRecord& a, const SampleRecord& b) { return a.index < b.index; });
  if (!complete) {
    std::uint64_t next = 0;
    std::vector<SampleRecord> missing;
    for (const auto& [a, b] : held) {
      for (std::uint64_t k = next; k < a; ++k)
        missing.push_back(runner.failed_record(k, ensemble::SampleStatus::not_run, "not in the merged parts"));
      next = b;
    }
    for (std::uint64_t k = next; k < spec.samples; ++k)
      missing.push_back(runner.failed_record(k, ensemble::SampleStatus::not_run, "not in the merged parts"));
    for (auto& r : missing) records.push_back(std::move(r));
  }

  try {
    EnsembleWriter writer(output_path, job, spec, runner.layout(), runner.final_state_size());
    writer.write_records(std::move(records));
    writer.write_nominal(parts[0].nominal);
    writer.write_statistics(stats);
    const std::vector<ensemble::ResponseAnswer> answers =
        table ? ensemble::answer_responses(spec, *table) : std::vector<ensemble::ResponseAnswer>{};
    writer.write_answers(answers);
    writer.write_merge_origin(names, held);
    // One process did the merge; the parts' own runs are described by them.
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    summary.ranks = 1;
    summary.peak_rss_mib = {static_cast<double>(usage.ru_maxrss) / 1024.0};
    summary.samples_per_rank = {0};
    summary.busy_seconds = {0.0};
    writer.finish(summary, run);
    if (!quiet && table) ensemble::print_response_summary(std::cout, spec, answers);
  } catch (const h5::IoError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitIo;
  }
  std::printf("wrote %s (%llu of %llu samples from %zu parts)\n", output_path.c_str(),
              static_cast<unsigned long long>(holding), static_cast<unsigned long long>(spec.samples), parts.size());
  return kExitOk;
}

}  // namespace treedyn
