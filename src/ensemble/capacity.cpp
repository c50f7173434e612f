#include "ensemble/capacity.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "common/host_time.hpp"
#include "designs/design_rules.hpp"
#include "ensemble/sample_rows.hpp"
#include "ensemble/sample_runner.hpp"
#include "persistence/record_codec.hpp"
#include "process/atomic_file.hpp"
#include "process/write_cost.hpp"

namespace treedyn::ensemble {
namespace {

struct OverBudget {};

}  // namespace

double rank_zero_seconds_per_record(std::size_t bytes) {
  // A fixed part per record (the message's share, the response table) and
  // a part per byte (decoding, the scatter into every per-sample dataset,
  // deflate).
  return kRankZeroFixedSeconds + kRankZeroSecondsPerByte * static_cast<double>(bytes);
}

double rank_zero_seconds_per_unit_record(std::size_t datasets, std::size_t rows, std::size_t row_bytes,
                                         double write_seconds_per_byte) {
  return kUnitRecordSeconds + write_seconds_per_byte * kStoredShare * static_cast<double>(row_bytes) +
         kChunkWriteSeconds * static_cast<double>(datasets) / static_cast<double>(rows);
}

double Capacity::seconds_per_record(std::size_t unit_rows) const {
  return unit_rows > 0 ? rank_zero_seconds_per_unit_record(datasets, unit_rows, row_bytes, write_seconds_per_byte)
                       : record_seconds;
}

void count_rows(Capacity& c, const SampleRows& rows) {
  c.datasets = rows.datasets().size();
  c.row_bytes = 0;
  for (const SampleRows::Dataset& d : rows.datasets()) c.row_bytes += d.row_bytes;
  c.most_unit_rows = most_unit_rows(rows);
}

void measure_writing(Capacity& c, const std::filesystem::path& dir) {
  try {
    c.write_seconds_per_byte = process::measure_write_seconds_per_byte(dir);
    c.write_measured_in = dir.string();
  } catch (const process::FileError& e) {
    c.write_seconds_per_byte = kDevelopmentWriteSecondsPerByte;
    c.write_not_measured = e.what();
  }
}

// Rank 0's cost per record grows with P (smaller units, then records): the
// ranks it keeps up with fall as P grows, and the first P beyond them ends
// the scan (doubling, then halving the step).
Scale scales_to(const Capacity& c, const EnsembleSpec& spec) {
  const std::uint64_t kMostRanks =
      std::max<std::uint64_t>(1, std::min<std::uint64_t>(spec.runs, std::uint64_t{1} << 24));
  const auto keeps_up = [&](std::uint64_t p) {
    return static_cast<double>(p) <= c.ranks(unit_rows(spec, static_cast<int>(p), c.most_unit_rows));
  };
  std::uint64_t good = 1, step = 1;
  while (good + step <= kMostRanks && keeps_up(good + step)) {
    good += step;
    step *= 2;
  }
  for (; step > 0; step /= 2)
    if (good + step <= kMostRanks && keeps_up(good + step)) good += step;
  return {good, unit_rows(spec, static_cast<int>(good), c.most_unit_rows)};
}

std::size_t most_unit_rows(const SampleRows& rows) {
  std::size_t unit = 0, widest = 1;
  for (const SampleRows::Dataset& d : rows.datasets()) {
    unit += d.row_bytes;
    widest = std::max(widest, d.row_bytes);
  }
  std::size_t most = kMaxUnitRows;
  while (most > 1 && (most * widest > kMaxChunkBytes || most * unit > kMaxUnitBytes)) most /= 2;
  return most;
}

std::size_t unit_rows(const EnsembleSpec& spec, int ranks, std::size_t most) {
  // An adaptive design's records arrive as its waves make them (chain by
  // chain), not in units.
  if (ranks < 2 || designs::rules_of(spec.design).adaptive(spec)) return 0;
  // A stopping rule's waves are `every` runs each: the units are of a wave.
  const std::uint64_t wave = spec.stop ? std::min<std::uint64_t>(spec.runs, spec.stop->every) : spec.runs;
  std::size_t rows = std::min(most, kMaxUnitRows);
  while (rows >= kMinUnitRows && wave < kUnitsPerRank * static_cast<std::uint64_t>(ranks) * rows) rows /= 2;
  return rows >= kMinUnitRows ? rows : 0;
}

std::size_t typical_record_bytes(const SampleRecord& record) {
  return persistence::encoded_size(record) - record.trajectory.size() * sizeof(double);
}

Capacity measure_capacity(const Job& job, const EnsembleSpec& spec, double budget) {
  SampleRunner runner(job, spec);
  std::vector<double> trajectory;
  const double start = thread_cpu_seconds();
  runner.run(0, true, trajectory);
  Capacity c;
  c.sample_seconds = std::numeric_limits<double>::infinity();
  // The fastest of up to 3 runs of sample 0 within the budget: the first
  // runs touch memory for the first time and run slower.
  for (int k = 0; k < 3 && (k == 0 || thread_cpu_seconds() - start < budget); ++k) {
    const double from = thread_cpu_seconds();
    SampleRecord record;
    try {
      record = runner.run(0, false, trajectory, [&] {
        if (thread_cpu_seconds() - start > budget) throw OverBudget{};
      });
    } catch (const OverBudget&) {
      c.sample_cut = k == 0;
      record = runner.failed_record(0, SampleStatus::integration_failed, "");
    }
    if (k == 0 || !c.sample_cut) c.sample_seconds = std::min(c.sample_seconds, thread_cpu_seconds() - from);
    c.record_bytes = std::max(c.record_bytes, typical_record_bytes(record));
    if (c.sample_cut) break;
  }
  c.record_seconds = rank_zero_seconds_per_record(c.record_bytes);
  count_rows(c, SampleRows(spec, runner.layout(), runner.final_state_size()));
  return c;
}

namespace {

std::string formatted(const char* format, auto... values) {
  std::string text(static_cast<std::size_t>(std::snprintf(nullptr, 0, format, values...)), '\0');
  std::snprintf(text.data(), text.size() + 1, format, values...);
  return text;
}

}  // namespace

void print_capacity(std::ostream& out, const Capacity& c, const EnsembleSpec& spec, const char* timed) {
  const Scale scale = scales_to(c, spec);
  const char* more = c.sample_cut ? "more than " : "";
  out << formatted(
             "rank 0's capacity: it takes in about %.0f records/s of this job's size as records (%zu bytes "
             "each), %.0f/s in units of %zu rows (%zu chunks each; %zu row bytes a record, about %.0f stored, ",
             1.0 / c.record_seconds, c.record_bytes, 1.0 / c.seconds_per_record(c.most_unit_rows), c.most_unit_rows,
             c.datasets, c.row_bytes, kStoredShare * static_cast<double>(c.row_bytes))
      << (c.write_measured_in.empty()
              ? formatted("at the development machine's %.2f ns a byte, not measured here: %s",
                          c.write_seconds_per_byte * 1e9, c.write_not_measured.c_str())
              : formatted("at %.2f ns a byte of page-cache CPU measured now in %s (a lower bound: "
                          "BENCHMARKS.md, \"Rank 0's storing\")",
                          c.write_seconds_per_byte * 1e9, c.write_measured_in.c_str()))
      << "; the rest measured on the development machine: BENCHMARKS.md); "
      << formatted(
             "at %s%.3g ms per sample (%s) this job's %llu runs scale to %sabout %llu ranks before rank 0 "
             "limits them",
             more, c.sample_seconds * 1e3, timed, static_cast<unsigned long long>(spec.runs), more,
             static_cast<unsigned long long>(scale.ranks));
  if (scale.ranks >= spec.runs)
    out << " (one run per rank: more ranks would idle)";
  else if (scale.unit_rows > 0)
    out << " (in units of " << scale.unit_rows << " rows)";
  else
    out << " (as records: too few runs for units)";
  const double most = std::floor(c.ranks(c.most_unit_rows));
  if (scale.unit_rows < c.most_unit_rows && most > static_cast<double>(scale.ranks))
    out << formatted("; with %llu runs per rank or more, to %sabout %.0f",
                     static_cast<unsigned long long>(kUnitsPerRank * c.most_unit_rows), more, most);
  out << "\n";
}

}  // namespace treedyn::ensemble
