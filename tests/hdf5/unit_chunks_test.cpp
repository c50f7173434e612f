// Units (hdf5/unit_chunks.hpp): a sender lays a unit's records out as one
// whole chunk of every per-sample dataset and compresses each itself; rank
// 0 stores them as they are. The file must then hold what rank 0 would have
// written from the records, value for value, whichever chunks were deflated
// or stored raw; a unit that is not one whole chunk, or a damaged message,
// must be refused with nothing written.
#include "hdf5/unit_chunks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <vector>

#include "common/bytes.hpp"
#include "ensemble/sample_runner.hpp"
#include "hdf5/ensemble_file.hpp"
#include "job/sample_job.hpp"
#include "statistics/calibration.hpp"
#include "support/command.hpp"
#include "support/ensemble_run.hpp"
#include "support/hdf5_reader.hpp"

namespace treedyn {
namespace {

namespace fs = std::filesystem;
using namespace treedyn::testing;

constexpr std::size_t kRows = 32, kRuns = 4 * kRows;

// The spherical pendulum over 0.2 s: real records (the sampled inputs are
// random numbers, which deflate cannot shrink; the statuses and the base's
// columns are constant, which it can), one of them failed with a reason.
struct Records {
  Records() {
    EnsembleJob read = read_ensemble_job(JobDocument::parse(
        edited_job_text("spherical_pendulum.toml", {{"end_time = 10.0", "end_time = 0.2"}}), "spherical.toml"));
    job = std::move(read.job);
    spec = std::move(read.spec);
    spec.runs = kRuns;
    spec.store_trajectories = 0;
    runner.emplace(job, spec);
    std::vector<double> trajectory;
    for (std::uint64_t k = 0; k < kRuns; ++k)
      all.push_back(k == 45 ? runner->failed_record(k, SampleStatus::integration_failed, "too much work")
                            : runner->run(k, false, trajectory));
  }
  std::vector<SampleRecord> slice(std::size_t first, std::size_t rows) const {
    return {all.begin() + static_cast<long>(first), all.begin() + static_cast<long>(first + rows)};
  }
  Job job;
  EnsembleSpec spec;
  std::optional<ensemble::SampleRunner> runner;
  std::vector<SampleRecord> all;
};

const Records& records() {
  static const Records r;
  return r;
}

std::vector<char> encoded(const ensemble::SampleRows& rows, std::vector<SampleRecord> run) {
  std::vector<char> message;
  h5::UnitEncoder(rows).encode(run, message);
  return message;
}

class UnitChunks : public ::testing::Test {
 protected:
  void SetUp() override { h5::quiet_errors(); }
  // A file of every row written by rank 0 from the records, complete.
  fs::path from_records(std::size_t unit_rows) {
    const fs::path path = dir_.path() / ("records_" + std::to_string(unit_rows) + ".h5");
    const Records& r = records();
    h5::EnsembleWriter writer(path, r.job, r.spec, r.runner->layout(), r.runner->final_state_size(), unit_rows);
    writer.write_records(r.all);
    complete(writer);
    return path;
  }
  void complete(h5::EnsembleWriter& writer) {
    const Records& r = records();
    const std::size_t columns = r.runner->layout().columns, entries = r.runner->times() * columns;
    const std::vector<double> zero(entries, 0.0), low(entries, -1.0), high(entries, 1.0), scale(columns, 1.0);
    statistics::EnsembleStatistics stats(r.runner->times(), columns, 8,
                                         statistics::calibrate(zero, low, high, scale, columns, 8));
    ensemble::RunSummary one_rank;  // one value per rank in every per-rank attribute
    one_rank.peak_rss_mib = one_rank.busy_seconds = one_rank.writing_seconds = {0.0};
    one_rank.busy_cpu_seconds = one_rank.writing_cpu_seconds = one_rank.cpu_seconds = {0.0};
    one_rank.samples_per_rank = {0};
    writer.complete(zero, stats, {}, {}, one_rank, h5::RunProvenance{}, std::chrono::steady_clock::now());
  }
  TempDir dir_{"unit_chunks"};
};

// Rows 0 .. 31 as records, then three units: rows 32 .. 127. Every dataset
// under /samples reads back the same bytes as a file written from records
// alone (with 64 KiB chunks); both deflated and raw chunks were sent.
TEST_F(UnitChunks, UnitsReadBackAsTheRowsRankZeroWritesFromRecords) {
  const Records& r = records();
  const fs::path path = dir_.path() / "units.h5";
  std::size_t deflated = 0, raw = 0;
  {
    h5::EnsembleWriter writer(path, r.job, r.spec, r.runner->layout(), r.runner->final_state_size(), kRows);
    writer.write_records(r.slice(0, kRows));
    h5::Unit unit;  // decoded into again and again, as rank 0 does (the first holds the failed sample)
    for (std::size_t first = kRows; first < kRuns; first += kRows) {
      const std::vector<char> message = encoded(writer.sample_rows(), r.slice(first, kRows));
      h5::decode_unit_into(message, writer.sample_rows().datasets().size(), "a test unit", unit);
      ASSERT_EQ(unit.first, first);
      ASSERT_EQ(unit.records.size(), kRows);
      for (const h5::UnitChunk& c : unit.chunks) ++(c.deflated ? deflated : raw);
      for (std::size_t k = 0; k < kRows; ++k) {  // stripped of the rows, the rest as it was
        const SampleRecord &sent = unit.records[k], &made = r.all[first + k];
        EXPECT_EQ(sent.index, made.index);
        EXPECT_EQ(sent.status, made.status);
        EXPECT_EQ(sent.reason, made.reason);
        EXPECT_EQ(sent.inputs, made.inputs);
        EXPECT_TRUE(sent.reductions.empty() && sent.final_state.empty() && sent.trajectory.empty());
      }
      writer.write_unit(unit);
    }
    complete(writer);
  }
  EXPECT_GT(deflated, 0u);
  EXPECT_GT(raw, 0u) << "no chunk went raw: the inputs' rows should";
  H5File units(path), plain(from_records(0));
  ASSERT_TRUE(units.ok() && plain.ok());
  expect_identical_datasets(plain.id(), "from records", units.id(), "units", {"/samples"});
  EXPECT_EQ(read_strings(units.id(), "/samples/reason")[45], "too much work");
  // Only the failed sample's reason was written: the chunk holding row 45
  // is stored (one of 4 in units of 32 rows; the one of the file from
  // records), the others are not (rows never written: null strings, read
  // as empty).
  for (const H5File* f : {&units, &plain}) {
    const hid_t reason = H5Dopen2(f->id(), "/samples/reason", H5P_DEFAULT);
    ASSERT_GE(reason, 0);
    const hid_t space = H5Dget_space(reason);
    hsize_t stored = 0;
    ASSERT_GE(H5Dget_num_chunks(reason, space, &stored), 0);
    EXPECT_EQ(stored, 1u);
    H5Sclose(space);
    H5Dclose(reason);
  }
  const std::vector<double> final_state = read_doubles(units.id(), "/samples/final_state");
  EXPECT_TRUE(std::isnan(final_state[45 * (final_state.size() / kRuns)]));
}

// A unit over rows some records already wrote (not a case a run makes: a
// unit's rows are its own) is written as rows: the same values.
TEST_F(UnitChunks, AUnitOverRowsAlreadyWrittenIsWrittenAsRows) {
  const Records& r = records();
  const fs::path path = dir_.path() / "overlap.h5";
  {
    h5::EnsembleWriter writer(path, r.job, r.spec, r.runner->layout(), r.runner->final_state_size(), kRows);
    writer.write_records(r.slice(0, kRows + 5));
    const std::vector<char> message = encoded(writer.sample_rows(), r.slice(kRows, kRows));
    writer.write_unit(h5::decode_unit(message, writer.sample_rows().datasets().size(), "a test unit"));
    writer.write_records(r.slice(2 * kRows, kRuns - 2 * kRows));
    complete(writer);
  }
  H5File overlap(path), plain(from_records(kRows));
  ASSERT_TRUE(overlap.ok() && plain.ok());
  expect_identical_datasets(plain.id(), "from records", overlap.id(), "a unit over records", {"/samples"});
}

// A unit that is not one whole chunk is refused (IoError) before anything
// of it is written: its rows read as never written.
TEST_F(UnitChunks, AUnitThatIsNotOneWholeChunkIsRefused) {
  const Records& r = records();
  const fs::path path = dir_.path() / "refused.h5";
  h5::EnsembleWriter writer(path, r.job, r.spec, r.runner->layout(), r.runner->final_state_size(), kRows);
  for (std::size_t first : {std::size_t{5}, std::size_t{kRows}}) {
    const std::size_t rows = first == 5 ? kRows : kRows / 2;  // misaligned; too short
    const std::vector<char> message = encoded(writer.sample_rows(), r.slice(first, rows));
    const h5::Unit unit = h5::decode_unit(message, writer.sample_rows().datasets().size(), "a test unit");
    try {
      writer.write_unit(unit);
      ADD_FAILURE() << "rows " << first << " + " << rows << " accepted";
    } catch (const h5::IoError& e) {
      EXPECT_NE(std::string(e.what()).find("is not one whole chunk of 32 rows"), std::string::npos) << e.what();
    }
  }
  writer.write_records(r.slice(2 * kRows, 2 * kRows));
  complete(writer);
  H5File f(path);
  ASSERT_TRUE(f.ok());
  const std::vector<long long> status = read_integers(f.id(), "/samples/status");
  for (std::size_t k = 0; k < 2 * kRows; ++k) EXPECT_EQ(status[k], 3) << "row " << k << " was written";
}

// A damaged message: cut short, or of another number of datasets, or with
// records that are not its rows (one more, or more than any message could
// hold): a DecodeError that says so.
TEST_F(UnitChunks, ADamagedUnitIsADecodeErrorNamingIt) {
  const Records& r = records();
  const ensemble::SampleRows rows(r.spec, r.runner->layout(), r.runner->final_state_size());
  const std::vector<char> message = encoded(rows, r.slice(0, kRows));
  const std::size_t datasets = rows.datasets().size();
  const auto refused = [&](std::span<const char> bytes, std::size_t count, const char* why) {
    try {
      h5::decode_unit(bytes, count, "the unit of rank 2");
      ADD_FAILURE() << why << ": accepted";
    } catch (const DecodeError& e) {
      EXPECT_NE(std::string(e.what()).find("the unit of rank 2 is damaged"), std::string::npos) << e.what();
    }
  };
  refused(std::span<const char>(message).first(message.size() - 3), datasets, "cut short");
  refused(message, datasets + 1, "another number of datasets");
  std::vector<char> more_rows = message;
  more_rows[8] = static_cast<char>(kRows + 1);  // the row count, little-endian
  refused(more_rows, datasets, "a row count its records do not match");
  std::vector<char> huge_rows = message;
  huge_rows[15] = 0x10;  // 2^60 rows: refused before any memory is asked for them
  refused(huge_rows, datasets, "a row count no message could hold");
}

}  // namespace
}  // namespace treedyn
