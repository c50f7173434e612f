// The ensemble service through the real `treedyn-ensemble` binary under
// mpirun (Open MPI, --oversubscribe: CI has 2 cores and some cases start 3
// ranks). Every run is wrapped in `timeout`, so a hang fails the test instead
// of blocking CI. Output goes to a fresh temporary directory per test, removed
// afterwards. HDF5 is read back through the C API.
//
//   1. Same numbers on any number of ranks: one job (a branched 3-body tree,
//      orientation + mass + angular-velocity perturbations, 40 samples, 8
//      pilot samples, blocks of 2) run by the binary alone and under mpirun
//      with 1, 2 and 3 ranks. Every dataset under /stats, /samples and
//      /nominal is compared BYTE FOR BYTE (raw read in the file's native
//      type), as are the root attributes seed, samples, samples_ok and
//      samples_failed; `ranks` is 1, 1, 2, 3.
//   2. Failed samples are handled: a job whose samples fail on purpose (a
//      normal(1, 1) mass, so some masses are negative -> invalid model, status
//      2; a wide spin range with a small max_steps -> too_much_work, status 1)
//      completes with exit 0 and records every failure; 1 and 2 ranks agree
//      byte for byte.
//   3. A bad job fails on every rank without hanging: exit 2 on 3 ranks,
//      within the timeout, one "error: FILE:LINE:COL: FIELD: ..." message,
//      no output or temporary file left.
//   4. Every shipped example (jobs/*.toml) runs its [ensemble] on 2 ranks:
//      exit 0, every sample ok, and /stats, /samples and /nominal have the
//      documented shapes (docs/hdf5.md, "HDF5 ensemble layout").
#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "job/ensemble_spec.hpp"
#include "job/job.hpp"
#include "output/quantities.hpp"
#include "support/branched_tree.hpp"
#include "support/command.hpp"
#include "support/ensemble_run.hpp"
#include "support/hdf5_reader.hpp"

namespace {

namespace fs = std::filesystem;

using namespace treedyn::testing;

// The names in `dir` (files and directories), sorted.
std::vector<std::string> listing(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// A successful run: exit 0, "wrote OUTPUT" on stdout, and in the output's
// directory the output file and no temporary (OUTPUT.tmp-PID).
void expect_success(const CommandResult& r, const fs::path& output) {
  EXPECT_EQ(r.exit_code, 0) << "stdout:\n" << r.out << "stderr:\n" << r.err;
  EXPECT_NE(r.out.find("wrote " + output.string()), std::string::npos) << r.out;
  EXPECT_EQ(r.err.find("error"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(output)) << output;
  for (const auto& name : listing(output.parent_path()))
    EXPECT_EQ(name.find(".tmp-"), std::string::npos) << "temporary file left behind: " << name;
}

std::string with(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  if (at == std::string::npos) throw std::invalid_argument("not in the job: " + from);
  return text.replace(at, from.size(), to);
}

// ---------------------------------------------------------------------------
// HDF5 through the C API

// ---------------------------------------------------------------------------
// 1. Same numbers on any number of ranks

// A branched 3-body tree under gravity (a trunk hung from the base carrying an
// arm and a bob) with three perturbations of mixed kinds: the trunk's start
// orientation (3 inputs), the bob's mass, the arm's spin.
const std::string kTreeJob =
    "title = \"ensemble mpi test: branched 3-body tree\"\n" + kBranchedTreeModel + R"([ensemble]
samples = 40
seed = 42
design = "latin_hypercube"
pilot_samples = 8
block_size = 2
histogram_bins = 16
quantiles = [0.1, 0.5, 0.9]

[[ensemble.perturbation]]
target = "body.trunk.orientation"
distribution = "normal"
std = 2.0
unit = "deg"

[[ensemble.perturbation]]
target = "body.bob.mass"
distribution = "truncated_normal"
mean = 0.3
std = 0.05
lower = 0.2
upper = 0.4

[[ensemble.perturbation]]
target = "body.arm.angular_velocity.z"
distribution = "uniform"
lower = 1.0
upper = 3.0
)";

constexpr long long kTreeSamples = 40, kTreePilot = 8;

TEST(EnsembleMpi, SameNumbersAloneAndOnOneTwoAndThreeRanks) {
  TempDir dir("ensemble_mpi_ranks");
  const fs::path job = dir.path() / "tree.toml";
  write_text(job, kTreeJob);

  const std::vector<int> runs = {0, 1, 2, 3};  // 0: the binary without mpirun
  std::vector<fs::path> outputs;
  for (int ranks : runs) {
    const fs::path out_dir = dir.path() / ("out_" + std::to_string(ranks));
    fs::create_directory(out_dir);
    outputs.push_back(out_dir / "ensemble.h5");
    const auto r = run_ensemble(ranks, job, outputs.back(), dir.path() / "capture");
    std::printf("[same numbers] %s: exit %d in %.2f s\n", describe(ranks).c_str(), r.exit_code, r.seconds);
    SCOPED_TRACE(describe(ranks));
    expect_success(r, outputs.back());
    EXPECT_EQ(listing(out_dir), std::vector<std::string>{"ensemble.h5"});
  }

  H5File reference(outputs[0]);
  ASSERT_TRUE(reference.ok());
  const hid_t ref = reference.id();
  EXPECT_EQ(read_integer_attribute(ref, "samples"), kTreeSamples);
  EXPECT_EQ(read_integer_attribute(ref, "samples_ok"), kTreeSamples);
  EXPECT_EQ(read_integer_attribute(ref, "samples_failed"), 0);
  EXPECT_EQ(read_integer_attribute(ref, "seed"), 42);

  // The comparison is not vacuous: the perturbations spread the results.
  {
    const auto sd = read_doubles(ref, "/stats/energy/std");
    ASSERT_EQ(sd.size(), 41u * 4u);
    EXPECT_GT(sd[40 * 4 + 3], 0.0) << "no spread in the final total energy";
    const auto inputs = read_doubles(ref, "/samples/inputs");
    ASSERT_EQ(inputs.size(), static_cast<std::size_t>(kTreeSamples) * 5u);
    EXPECT_NE(inputs[3], inputs[5 + 3]) << "samples 0 and 1 drew the same mass";
  }

  for (std::size_t i = 0; i < runs.size(); ++i) {
    const int ranks = runs[i];
    SCOPED_TRACE(describe(ranks));
    H5File file(outputs[i]);
    ASSERT_TRUE(file.ok());
    const hid_t f = file.id();
    EXPECT_EQ(read_integer_attribute(f, "ranks"), std::max(ranks, 1));
    for (const char* a : {"seed", "samples", "samples_ok", "samples_failed"})
      EXPECT_EQ(read_integer_attribute(f, a), read_integer_attribute(ref, a)) << "attribute " << a;
    // Every rank integrated: the pilot samples go round-robin, so with P
    // ranks rank r runs at least floor(8 / P) of them.
    const auto per_rank = read_double_attribute(f, "samples_per_rank");
    ASSERT_EQ(per_rank.size(), static_cast<std::size_t>(std::max(ranks, 1)));
    EXPECT_EQ(std::accumulate(per_rank.begin(), per_rank.end(), 0.0), static_cast<double>(kTreeSamples));
    for (double n : per_rank) EXPECT_GE(n, static_cast<double>(kTreePilot / std::max(ranks, 1)));
    if (i == 0) continue;
    expect_identical_datasets(ref, describe(runs[0]), f, describe(ranks), {"/stats", "/samples", "/nominal"});
  }
}

// The job run alone (no mpirun) and on 2 ranks, each successful: the two
// outputs.
std::pair<fs::path, fs::path> run_alone_and_on_two_ranks(const TempDir& dir, const fs::path& job,
                                                         const std::vector<std::string>& extra = {}) {
  std::vector<fs::path> outputs;
  for (int ranks : {0, 2}) {
    outputs.push_back(dir.path() / ("out_" + std::to_string(ranks) + ".h5"));
    const auto r = run_ensemble(ranks, job, outputs.back(), dir.path() / "capture", extra);
    SCOPED_TRACE(describe(ranks));
    expect_success(r, outputs.back());
  }
  return {outputs[0], outputs[1]};
}

// A row never written reads as the datasets' fill (status 3, zeros
// elsewhere), so check what every written row of `samples` successful
// samples has: status ok, the end time reached, steps.
void expect_every_row_written(hid_t file, std::size_t samples, double end_time) {
  EXPECT_EQ(read_integers(file, "/samples/status"), std::vector<long long>(samples, 0));
  EXPECT_EQ(read_doubles(file, "/samples/time_reached"), std::vector<double>(samples, end_time));
  const std::vector<long long> stats = read_integers(file, "/samples/integrator_stats");
  ASSERT_EQ(stats.size() % samples, 0u);
  for (std::size_t k = 0; k < samples; ++k)
    if (stats[k * (stats.size() / samples)] <= 0) {
      ADD_FAILURE() << "sample " << k << " has no steps: its row was not written";
      break;
    }
}

// Rank 0 holds the records that arrive and writes them in batches once
// 4 MiB are held, the last ones when the run is complete
// (mpi/parallel/record_sink.hpp). 50 spherical-pendulum samples carrying
// their full trajectory (about 420 KB a record) are written as 4 batches of
// 12 during the run and 2 at its end: every record and every trajectory
// must reach the file, with the same bytes alone and on 2 ranks.
TEST(EnsembleMpi, RecordsWrittenInSeveralBatchesAllReachTheFile) {
  TempDir dir("ensemble_mpi_batches");
  const fs::path job = dir.path() / "spherical.toml";
  write_text(job, edited_job_text("spherical_pendulum.toml",
                                  {{"samples = 64", "samples = 50\nstore_trajectories = 50\nblock_size = 2"}}));
  const auto [alone_path, two_path] = run_alone_and_on_two_ranks(dir, job);
  H5File alone(alone_path), two(two_path);
  ASSERT_TRUE(alone.ok() && two.ok());
  expect_every_row_written(two.id(), 50, 10.0);
  const std::vector<double> tip = read_doubles(two.id(), "/trajectories/point_position");
  ASSERT_EQ(tip.size(), 50u * 1001u * 3u);
  EXPECT_TRUE(std::all_of(tip.begin(), tip.end(), [](double x) { return std::isfinite(x); }))
      << "a stored trajectory is missing (NaN rows)";
  EXPECT_NE(tip[3 * 1001 * 49 + 3 * 1000], tip[3 * 1000]) << "samples 0 and 49 ended at the same tip x";
  expect_identical_datasets(alone.id(), "alone", two.id(), "2 ranks", {"/samples", "/trajectories", "/stats"});
}

// Rank 0 writes the records that arrive while it integrates a sample of its
// own (RecordSink::poll). That time is writing, not the sample's: it goes
// into record_writing_seconds_per_rank, and busy_seconds_per_rank leaves it
// out. Every write into the output is made 5 ms slower (io_faults): rank 0
// then writes for about 4.5 s (some 900 writes), in batches of 12 records
// that are mostly set off by a message received inside one of its samples.
// Counted as busy too, that made rank 0's busy time per sample about 50x
// rank 1's (205 against 3.8 ms, measured); counted apart, about 1.4x. (A
// schedule in which every batch were set off between samples would pass
// without testing the subtraction; none was seen.)
TEST(EnsembleMpi, RankZeroCountsItsRecordWritingApartFromItsSamples) {
  TempDir dir("ensemble_mpi_writing_time");
  const fs::path job = dir.path() / "spherical.toml";
  write_text(job, edited_job_text("spherical_pendulum.toml",
                                  {{"samples = 64", "samples = 50\nstore_trajectories = 50\nblock_size = 2"}}));
  const fs::path out = dir.path() / "out_slow.h5";
  // clang-format off
  const std::vector<std::string> prefix = {
      "env", std::string("LD_PRELOAD=") + TREEDYN_IO_FAULTS_LIBRARY, "TREEDYN_TEST_SLOW_WRITE=out_slow.h5.tmp-",
      "ASAN_OPTIONS=detect_leaks=0:abort_on_error=1:verify_asan_link_order=0",
      "timeout", "-k", "10", std::to_string(kTimeoutSeconds), TREEDYN_MPIEXEC, "--oversubscribe", "-np", "2"};
  // clang-format on
  const auto r =
      run_command(TREEDYN_ENSEMBLE_BINARY, {job.string(), "-o", out.string(), "-q"}, dir.path() / "capture", prefix);
  expect_success(r, out);
  H5File file(out);
  ASSERT_TRUE(file.ok());
  const double wall = read_double_attribute(file.id(), "wall_time_seconds").at(0);
  const auto busy = read_double_attribute(file.id(), "busy_seconds_per_rank");
  const auto writing = read_double_attribute(file.id(), "record_writing_seconds_per_rank");
  const auto samples = read_double_attribute(file.id(), "samples_per_rank");
  ASSERT_EQ(busy.size(), 2u);
  ASSERT_EQ(writing.size(), 2u);
  ASSERT_EQ(samples.size(), 2u);
  // At least 100 writes (of some 900) counted.
  EXPECT_GT(writing[0], 0.5) << "rank 0's writing was not counted";
  EXPECT_EQ(writing[1], 0.0) << "rank 1 writes nothing: it sends";
  for (int rank : {0, 1}) {
    SCOPED_TRACE("rank " + std::to_string(rank));
    EXPECT_GT(busy[rank], 0.0);
    EXPECT_GT(samples[rank], 0.0);
    EXPECT_LE(busy[rank] + writing[rank], wall) << "the same time counted twice";
  }
  const double per_sample0 = busy[0] / samples[0], per_sample1 = busy[1] / samples[1];
  EXPECT_LT(per_sample0, 10.0 * per_sample1) << "rank 0's busy time per sample (" << per_sample0
                                             << " s) holds its writing; rank 1's is " << per_sample1 << " s";
}

// The rows in a chunk of a chunked dataset, and the bytes a chunk of it
// takes on disk before compression (read from a dataset stored raw: HDF5
// says what it allocated, whatever the type; a variable-length string is a
// 16-byte heap reference there).
std::pair<hsize_t, double> chunk_rows_and_bytes(hid_t file, const std::string& path, const fs::path& scratch_file) {
  Hid set(H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose);
  Hid plist(H5Dget_create_plist(set.get()), H5Pclose);
  Hid type(H5Dget_type(set.get()), H5Tclose);
  Hid space(H5Dget_space(set.get()), H5Sclose);
  hsize_t chunk[2] = {0, 0};
  const int rank = H5Pget_chunk(plist.get(), 2, chunk);
  if (rank < 0) ADD_FAILURE() << path << " is not chunked";
  hsize_t dims[2] = {0, 1};
  H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  // The same dataset uncompressed, one chunk long, in a scratch file.
  Hid scratch(H5Fcreate(scratch_file.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
  Hid raw_plist(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  H5Pset_chunk(raw_plist.get(), rank, chunk);
  H5Pset_alloc_time(raw_plist.get(), H5D_ALLOC_TIME_EARLY);
  const hsize_t one_chunk[2] = {chunk[0], dims[1]};
  Hid raw_space(H5Screate_simple(rank, one_chunk, nullptr), H5Sclose);
  Hid raw(H5Dcreate2(scratch.get(), "probe", type.get(), raw_space.get(), H5P_DEFAULT, raw_plist.get(), H5P_DEFAULT),
          H5Dclose);
  return {chunk[0], static_cast<double>(H5Dget_storage_size(raw.get()))};
}

// 20,000 short samples sent as records (--test-unit-rows 0; by default 2
// ranks would send units of 512 rows: checked last): every /samples
// dataset spans several chunks of about 64 KiB, and rank 0 writes its rows
// in about five batches, so most chunks receive rows in more than one
// write, from both ranks, out of order. Every row must hold its sample, the
// same bytes alone and on two ranks, and the chunks must be the size that
// keeps deflate's fixed cost per chunk small (a chunk of 64 rows cost rank
// 0 twice the time).
TEST(EnsembleMpi, ManyRowsWrittenInPiecesFillEveryChunk) {
  TempDir dir("ensemble_mpi_chunks");
  const fs::path job = dir.path() / "spherical.toml";
  constexpr std::size_t kSamples = 20000;
  write_text(job, edited_job_text("spherical_pendulum.toml", {{"samples = 64", "samples = 20000\nblock_size = 16"},
                                                              {"end_time = 10.0", "end_time = 0.02"}}));
  const auto [alone_path, two_path] = run_alone_and_on_two_ranks(dir, job, {"--test-unit-rows", "0"});
  H5File alone(alone_path), two(two_path);
  ASSERT_TRUE(alone.ok() && two.ok());
  expect_every_row_written(two.id(), kSamples, 0.02);
  for (const std::string path : {"/samples/status", "/samples/time_reached", "/samples/inputs", "/samples/final_state",
                                 "/samples/max/energy", "/samples/reason"}) {
    const auto [rows, bytes] = chunk_rows_and_bytes(two.id(), path, dir.path() / "chunk_probe.h5");
    EXPECT_LE(bytes, 65536.0) << path << ": " << rows << " rows a chunk";
    EXPECT_GT(bytes, 32768.0) << path << ": " << rows << " rows a chunk";
    EXPECT_LT(rows, kSamples) << path << ": one chunk would not test rows written in pieces";
  }
  expect_identical_datasets(alone.id(), "alone", two.id(), "2 ranks", {"/samples", "/stats"});
  // A row no record reached would read as status 3 (not run), not as 0 (ok).
  Hid status(H5Dopen2(two.id(), "/samples/status", H5P_DEFAULT), H5Dclose);
  Hid plist(H5Dget_create_plist(status.get()), H5Pclose);
  std::int32_t fill = 0;
  ASSERT_GE(H5Pget_fill_value(plist.get(), H5T_NATIVE_INT32, &fill), 0);
  EXPECT_EQ(fill, 3);
  // By default: 20,000 >= 16 units x 2 ranks x 512 rows (ensemble/capacity.hpp),
  // so rank 1 sends units of 512 rows, chunked so, the same bits.
  const fs::path units_path = dir.path() / "units.h5";
  const auto r = run_ensemble(2, job, units_path, dir.path() / "capture");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  H5File units(units_path);
  ASSERT_TRUE(units.ok());
  EXPECT_EQ(read_integer_attribute(units.id(), "unit_rows"), 512);
  EXPECT_GE(read_integer_attribute(units.id(), "samples_in_units"), 512);
  EXPECT_EQ(chunk_rows_and_bytes(units.id(), "/samples/final_state", dir.path() / "chunk_probe.h5").first, 512u);
  expect_identical_datasets(alone.id(), "alone", units.id(), "2 ranks, units", {"/samples", "/stats"});
}

// ---------------------------------------------------------------------------
// 2. Failed samples

// A rod with a ball at its end. The ball's mass is normal(1, 1): about one
// sample in six draws a negative mass (invalid model, status 2). The rod's
// spin about y is uniform in [0, 50] rad/s against max_steps = 200 per
// 0.1-s output interval: fast or light-tipped samples give up
// (too_much_work, status 1). The nominal run (no spin, 0.3 kg) succeeds.
const std::string kFailingJob = R"(title = "ensemble mpi test: failing samples"

[environment]
gravity = [0.0, 0.0, -9.81]

[[body]]
name = "rod"
shape = "cylinder"
radius = 0.02
length = 0.5
mass = 1.0
parent = "base"
joint_on_child = [0.0, 0.0, 0.25]
orientation = { type = "axis_angle", axis = [1, 0, 0], angle = 30, unit = "deg" }

[[body]]
name = "tip"
shape = "sphere"
radius = 0.05
mass = 0.3
parent = "rod"
joint_on_parent = [0.0, 0.0, -0.25]
joint_on_child = [0.0, 0.0, 0.05]

[integrator]
method = "erk_dormand_prince"
rtol = 1e-8
atol = 1e-10
max_steps = 200

[output]
end_time = 1.0
step = 0.1
quantities = ["energy", "com_position"]

[ensemble]
samples = 40
seed = 9
design = "monte_carlo"
pilot_samples = 8
block_size = 2
histogram_bins = 16

[[ensemble.perturbation]]
target = "body.tip.mass"
distribution = "normal"
mean = 1.0
std = 1.0

[[ensemble.perturbation]]
target = "body.rod.angular_velocity.y"
distribution = "uniform"
lower = 0.0
upper = 50.0
)";

constexpr double kFailingEndTime = 1.0;
constexpr std::size_t kFailingSamples = 40;

// The failing job run once with 1 rank and once with 2; the tests read the files.
class EnsembleFailures : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<TempDir>("ensemble_mpi_failures");
    const fs::path job = dir_->path() / "failing.toml";
    write_text(job, kFailingJob);
    for (int ranks : {1, 2}) {
      const fs::path out_dir = dir_->path() / ("out_" + std::to_string(ranks));
      fs::create_directory(out_dir);
      const fs::path output = out_dir / "ensemble.h5";
      results_[ranks] = run_ensemble(ranks, job, output, dir_->path() / "capture");
      outputs_[ranks] = output;
      std::printf("[failures] %s: exit %d in %.2f s\n", describe(ranks).c_str(), results_[ranks].exit_code,
                  results_[ranks].seconds);
    }
    // 3 ranks with units of 4 rows (--test-unit-rows): samples 8 .. 39 are
    // 8 units, which ranks 1 and 2 send as compressed chunks.
    const fs::path out_dir = dir_->path() / "out_units";
    fs::create_directory(out_dir);
    outputs_[kUnits] = out_dir / "ensemble.h5";
    results_[kUnits] = run_ensemble(3, job, outputs_[kUnits], dir_->path() / "capture", {"--test-unit-rows", "4"});
  }
  static constexpr int kUnits = -3;  // the key of the run with units
  static void TearDownTestSuite() { dir_.reset(); }

  static std::unique_ptr<TempDir> dir_;
  static std::map<int, CommandResult> results_;
  static std::map<int, fs::path> outputs_;
};
std::unique_ptr<TempDir> EnsembleFailures::dir_;
std::map<int, CommandResult> EnsembleFailures::results_;
std::map<int, fs::path> EnsembleFailures::outputs_;

struct FailureCounts {
  std::size_t ok = 0, integration = 0, invalid = 0;
};

// Every sample's row of the failing job: its status, reason, time reached
// and mass agree (a non-positive mass is an invalid model, whatever the
// spin; an integration failure says too_much_work and stopped early).
FailureCounts expect_consistent_rows(hid_t f) {
  const auto status = read_integers(f, "/samples/status");
  const auto reason = read_strings(f, "/samples/reason");
  const auto reached = read_doubles(f, "/samples/time_reached");
  const auto inputs = read_doubles(f, "/samples/inputs");
  FailureCounts n;
  if (status.size() != kFailingSamples || reason.size() != kFailingSamples || reached.size() != kFailingSamples ||
      inputs.size() != 2 * kFailingSamples) {
    ADD_FAILURE() << "rows: " << status.size() << ", " << reason.size() << ", " << reached.size() << ", "
                  << inputs.size() / 2;
    return n;
  }
  for (std::size_t k = 0; k < kFailingSamples; ++k) {
    SCOPED_TRACE("sample " + std::to_string(k) + ": status " + std::to_string(status[k]) + ", reason \"" + reason[k] +
                 "\"");
    const double mass = inputs[2 * k];
    if (mass <= 0.0) {
      EXPECT_EQ(status[k], 2);
    }
    if (status[k] == 0) {
      ++n.ok;
      EXPECT_EQ(reason[k], "");
      EXPECT_EQ(reached[k], kFailingEndTime);
    } else if (status[k] == 1) {
      ++n.integration;
      EXPECT_NE(reason[k].find("too_much_work"), std::string::npos);
      EXPECT_GE(reached[k], 0.0);
      EXPECT_LT(reached[k], kFailingEndTime);
    } else if (status[k] == 2) {
      ++n.invalid;
      EXPECT_NE(reason[k].find("mass"), std::string::npos);
      EXPECT_LE(mass, 0.0) << "a positive mass was refused";
    } else {
      ADD_FAILURE() << "status " << status[k] << " is not 0, 1 or 2";
    }
  }
  // Failures in the pilot as well as in the queue (samples 0..7 are the pilot).
  EXPECT_TRUE(std::any_of(status.begin(), status.begin() + 8, [](long long s) { return s != 0; }));
  EXPECT_TRUE(std::any_of(status.begin() + 8, status.end(), [](long long s) { return s != 0; }));
  return n;
}

// The statistics count exactly the `ok` successful samples, every entry,
// and so do the final-time histograms (bins + underflow + overflow).
void expect_statistics_count(hid_t f, std::size_t ok) {
  for (const std::string q : {"energy", "com_position"}) {
    SCOPED_TRACE("quantity " + q);
    const auto count = read_integers(f, "/stats/" + q + "/count");
    ASSERT_FALSE(count.empty());
    for (long long c : count) EXPECT_EQ(c, static_cast<long long>(ok));
    const auto dims = shape(f, "/stats/" + q + "/histogram/counts");
    ASSERT_EQ(dims.size(), 2u);
    const auto counts = read_integers(f, "/stats/" + q + "/histogram/counts");
    const auto under = read_integers(f, "/stats/" + q + "/histogram/underflow");
    const auto over = read_integers(f, "/stats/" + q + "/histogram/overflow");
    ASSERT_EQ(under.size(), dims[0]);
    ASSERT_EQ(over.size(), dims[0]);
    for (std::size_t c = 0; c < dims[0]; ++c) {
      long long total = under[c] + over[c];
      for (std::size_t b = 0; b < dims[1]; ++b) total += counts[c * dims[1] + b];
      EXPECT_EQ(total, static_cast<long long>(ok)) << "column " << c;
    }
  }
}

TEST_F(EnsembleFailures, TheJobCompletesAndEveryFailureIsRecorded) {
  for (int ranks : {1, 2}) {
    SCOPED_TRACE(describe(ranks));
    expect_success(results_[ranks], outputs_[ranks]);
    H5File file(outputs_[ranks]);
    ASSERT_TRUE(file.ok());
    const hid_t f = file.id();
    EXPECT_EQ(read_string_attribute(f, "/samples/inputs", "columns"),
              (std::vector<std::string>{"body.tip.mass", "body.rod.angular_velocity.y"}));
    const FailureCounts n = expect_consistent_rows(f);
    std::printf("[failures] %s: %zu ok, %zu integration failed, %zu invalid model\n", describe(ranks).c_str(), n.ok,
                n.integration, n.invalid);
    // The job exercises both kinds of failure, and some samples succeed.
    EXPECT_GT(n.ok, 0u);
    EXPECT_GT(n.integration, 0u);
    EXPECT_GT(n.invalid, 0u);
    EXPECT_EQ(read_integer_attribute(f, "samples"), static_cast<long long>(kFailingSamples));
    EXPECT_EQ(read_integer_attribute(f, "samples_ok"), static_cast<long long>(n.ok));
    EXPECT_EQ(read_integer_attribute(f, "samples_failed"), static_cast<long long>(n.integration + n.invalid));
    EXPECT_EQ(read_integer_attribute(f, "ranks"), ranks);
    expect_statistics_count(f, n.ok);
  }
}

TEST_F(EnsembleFailures, OneAndTwoRanksGiveIdenticalStatisticsAndSamples) {
  expect_success(results_[1], outputs_[1]);
  expect_success(results_[2], outputs_[2]);
  H5File one(outputs_[1]), two(outputs_[2]);
  ASSERT_TRUE(one.ok() && two.ok());
  for (const char* a : {"seed", "samples", "samples_ok", "samples_failed"})
    EXPECT_EQ(read_integer_attribute(one.id(), a), read_integer_attribute(two.id(), a)) << a;
  expect_identical_datasets(one.id(), describe(1), two.id(), describe(2), {"/stats", "/samples", "/nominal"});
}

// Units (hdf5/unit_chunks.hpp): rows that senders assembled into whole
// chunks and compressed themselves, failed samples among them (NaN rows,
// reasons), read back as the same values as rows rank 0 assembled, and
// the chunks are the units' rows.
TEST_F(EnsembleFailures, UnitsOnThreeRanksGiveTheBitsOfOneRank) {
  expect_success(results_[kUnits], outputs_[kUnits]);
  H5File one(outputs_[1]), units(outputs_[kUnits]);
  ASSERT_TRUE(one.ok() && units.ok());
  const hid_t f = units.id();
  EXPECT_EQ(read_integer_attribute(f, "unit_rows"), 4);
  EXPECT_EQ(read_integer_attribute(one.id(), "unit_rows"), 0);
  EXPECT_GE(read_integer_attribute(f, "samples_in_units"), 4) << "no unit was sent";
  EXPECT_GT(read_integer_attribute(f, "samples_failed"), 0);
  for (const char* a : {"samples_ok", "samples_failed"})
    EXPECT_EQ(read_integer_attribute(one.id(), a), read_integer_attribute(f, a)) << a;
  expect_identical_datasets(one.id(), describe(1), f, "3 ranks with units", {"/stats", "/samples", "/nominal"});
  // The failed samples' reasons in the units' rows, as rank 0 wrote them.
  const std::vector<long long> status = read_integers(f, "/samples/status");
  const std::vector<std::string> reason = read_strings(f, "/samples/reason");
  std::size_t failed_in_units = 0;
  for (std::size_t k = 8; k < status.size(); ++k)
    if (status[k] != 0) {
      ++failed_in_units;
      EXPECT_FALSE(reason[k].empty()) << "sample " << k;
    }
  EXPECT_GT(failed_in_units, 0u) << "no failure fell in a unit: the test does not see them";
}

// docs/hdf5.md and the dataset's description: /samples/final_state is "NaN when
// failed", for either kind of failure.
TEST_F(EnsembleFailures, FailedSamplesHaveNaNFinalState) {
  H5File file(outputs_[1]);
  ASSERT_TRUE(file.ok());
  const hid_t f = file.id();
  const auto status = read_integers(f, "/samples/status");
  const auto dims = shape(f, "/samples/final_state");
  ASSERT_EQ(dims, (std::vector<hsize_t>{kFailingSamples, 14}));
  const auto state = read_doubles(f, "/samples/final_state");
  ASSERT_EQ(status.size(), kFailingSamples);
  std::vector<std::size_t> not_nan;  // failed samples with numbers in their final state
  for (std::size_t k = 0; k < kFailingSamples; ++k) {
    const auto row = state.begin() + static_cast<long>(k * dims[1]);
    const auto end = row + static_cast<long>(dims[1]);
    if (status[k] == 0) {
      EXPECT_TRUE(std::all_of(row, end, [](double v) { return std::isfinite(v); }))
          << "sample " << k << " is ok but its final state is not finite";
    } else if (!std::all_of(row, end, [](double v) { return std::isnan(v); })) {
      not_nan.push_back(k);
    }
  }
  std::ostringstream list;
  for (std::size_t k : not_nan)
    list << "\n  sample " << k << " (status " << status[k] << "): q0..q3 = " << state[k * dims[1]] << ", "
         << state[k * dims[1] + 1] << ", " << state[k * dims[1] + 2] << ", " << state[k * dims[1] + 3];
  EXPECT_TRUE(not_nan.empty()) << not_nan.size()
                               << " failed samples have numbers, not NaN, in /samples/final_state "
                                  "(the state at the last output time they reached):"
                               << list.str();
}

// A failed sample rerun alone fails the same way, at the same time, and its
// trajectory up to the failure is written (what happened in sample k?).
TEST_F(EnsembleFailures, AFailedSampleRerunAloneFailsTheSameWay) {
  H5File file(outputs_[1]);
  ASSERT_TRUE(file.ok());
  const auto status = read_integers(file.id(), "/samples/status");
  const auto reason = read_strings(file.id(), "/samples/reason");
  const auto reached = read_doubles(file.id(), "/samples/time_reached");
  std::size_t k = 0;
  while (k < status.size() && status[k] != 1) ++k;
  ASSERT_LT(k, status.size()) << "no sample failed to integrate";
  const fs::path out = dir_->path() / "failed_sample.h5";
  const CommandResult r =
      run_command(TREEDYN_ENSEMBLE_BINARY,
                  {(dir_->path() / "failing.toml").string(), "--sample", std::to_string(k), "-o", out.string(), "-q"},
                  dir_->path() / "capture");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("sample " + std::to_string(k) + " fails as in the ensemble: " + reason[k]), std::string::npos)
      << r.out;
  H5File sample(out);
  ASSERT_TRUE(sample.ok());
  Hid group(H5Gopen2(sample.id(), "/sample", H5P_DEFAULT), H5Gclose);
  EXPECT_EQ(read_integer_attribute(group.get(), "status"), 1);
  EXPECT_EQ(read_single_string_attribute(group.get(), "reason"), reason[k]);
  EXPECT_EQ(read_double_attribute(group.get(), "time_reached").at(0), reached[k]);
  EXPECT_FALSE(exists(sample.id(), "/final_state"));
  const auto times = read_doubles(sample.id(), "/time");
  ASSERT_FALSE(times.empty());
  EXPECT_LE(times.back(), reached[k]);
}

// ---------------------------------------------------------------------------
// 3. A bad job fails on every rank without hanging

// Runs `job_text` on 3 ranks and checks: exit 2 within the timeout, ONE error
// message "error: JOB:PREFIX..." holding every one of `parts`, nothing
// written ("wrote" absent), no output or temporary file in the directory.
void expect_refused_on_three_ranks(const std::string& label, const std::string& job_text, const std::string& prefix,
                                   std::initializer_list<std::string> parts) {
  TempDir dir("ensemble_mpi_bad");
  const fs::path job = dir.path() / "bad.toml";
  write_text(job, job_text);
  const fs::path out_dir = dir.path() / "out";
  fs::create_directory(out_dir);
  const auto r = run_ensemble(3, job, out_dir / "ensemble.h5", dir.path() / "capture");
  const std::size_t first_line_end = r.err.find('\n');
  std::printf("[%s] exit %d in %.2f s: %s\n", label.c_str(), r.exit_code, r.seconds,
              r.err.substr(0, first_line_end).c_str());
  EXPECT_EQ(r.exit_code, 2) << (r.exit_code == 124 || r.exit_code == 137
                                    ? "mpirun was killed by the timeout: the ranks hung\n"
                                    : "")
                            << r.err;
  EXPECT_LT(r.seconds, 60.0);
  // Rank 0 prints the message; the other ranks fail silently the same way.
  // The launcher may add lines of its own (Open MPI 5 warns about network
  // interfaces): treedyn's are the lines that start with "error: ".
  const std::vector<std::string> errors = lines_starting_with(r.err, "error: ");
  ASSERT_EQ(errors.size(), 1u) << "expected ONE error message:\n" << r.err;
  EXPECT_EQ(errors[0].rfind("error: " + job.string() + ":" + prefix, 0), 0u)
      << "expected the message to start with\n  error: " << job.string() << ":" << prefix << "\ngot\n"
      << r.err;
  for (const std::string& part : parts)
    EXPECT_NE(r.err.find(part), std::string::npos) << "missing \"" << part << "\" in\n" << r.err;
  EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
  EXPECT_EQ(r.out.find("wrote"), std::string::npos) << r.out;
  EXPECT_TRUE(listing(out_dir).empty()) << "left behind: " << ::testing::PrintToString(listing(out_dir));
}

TEST(EnsembleMpiBadJob, UnknownKeyInEnsembleFailsOnEveryRank) {
  const std::string text = with(kTreeJob, "block_size = 2\n", "block_size = 2\nsampels = 10\n");
  expect_refused_on_three_ranks("unknown [ensemble] key", text,
                                value_position(text, "sampels = 10") + ": ensemble.sampels: ",
                                {"unknown key 'sampels'", "did you mean 'samples'?"});
}

TEST(EnsembleMpiBadJob, BadPerturbationTargetFailsOnEveryRank) {
  const std::string text = with(kTreeJob, "target = \"body.bob.mass\"", "target = \"body.bob.weight\"");
  expect_refused_on_three_ranks(
      "bad perturbation target", text,
      value_position(text, "target = \"body.bob.weight\"") + ": ensemble.perturbation[2].target: ",
      {"'body.bob.weight' is not a target", "body.bob.mass"});
}

TEST(EnsembleMpiBadJob, PerturbationOfAMissingBodyFailsOnEveryRank) {
  const std::string text = with(kTreeJob, "target = \"body.bob.mass\"", "target = \"body.nobody.mass\"");
  expect_refused_on_three_ranks(
      "perturbation of a missing body", text,
      value_position(text, "target = \"body.nobody.mass\"") + ": ensemble.perturbation[2].target: ",
      {"'nobody' is not a body of the model"});
}

TEST(EnsembleMpiBadJob, MalformedTomlFailsOnEveryRank) {
  const std::string text = with(kTreeJob, "seed = 42\n", "seed = 42 x\n");
  // The parser stops at the 'x'.
  expect_refused_on_three_ranks("malformed TOML", text, position_of(text, "42 x", 3) + ": not valid TOML: ", {"'x'"});
}

TEST(EnsembleMpiBadJob, MissingJobFileFailsOnEveryRank) {
  TempDir dir("ensemble_mpi_bad");
  const fs::path job = dir.path() / "no_such_job.toml";
  const fs::path out_dir = dir.path() / "out";
  fs::create_directory(out_dir);
  const auto r = run_ensemble(3, job, out_dir / "ensemble.h5", dir.path() / "capture");
  std::printf("[missing job file] exit %d in %.2f s\n", r.exit_code, r.seconds);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(lines_starting_with(r.err, "error: "),
            std::vector<std::string>{"error: " + job.string() + ": cannot open the job file for reading"})
      << r.err;
  EXPECT_TRUE(listing(out_dir).empty());
}

// ---------------------------------------------------------------------------
// 4. Every shipped example's ensemble on 2 ranks

std::vector<std::string> example_jobs() {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(TREEDYN_JOBS_DIR, ec))
    if (entry.path().extension() == ".toml") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

class EnsembleMpiExample : public ::testing::TestWithParam<std::string> {};

using Dims = std::vector<hsize_t>;

// docs/hdf5.md's /samples: one row per sample, every sample ok.
void expect_sample_rows(hid_t f, const treedyn::Job& job, const treedyn::EnsembleSpec& spec) {
  const hsize_t N = spec.runs, D = spec.input_dimensions(), n = static_cast<hsize_t>(job.model.n);
  EXPECT_EQ(shape(f, "/samples/status"), Dims{N});
  EXPECT_EQ(shape(f, "/samples/reason"), Dims{N});
  EXPECT_EQ(shape(f, "/samples/time_reached"), Dims{N});
  EXPECT_EQ(shape(f, "/samples/integrator_stats"), (Dims{N, treedyn::kIntegratorStatFields.size()}));
  EXPECT_EQ(shape(f, "/samples/final_state"), (Dims{N, 7 * n}));
  EXPECT_EQ(shape(f, "/samples/inputs"), (Dims{N, D}));
  EXPECT_EQ(read_string_attribute(f, "/samples/inputs", "columns").size(), D);
  for (long long s : read_integers(f, "/samples/status")) EXPECT_EQ(s, 0);
  for (const auto& s : read_strings(f, "/samples/reason")) EXPECT_EQ(s, "");
  for (double t : read_doubles(f, "/samples/time_reached")) EXPECT_EQ(t, job.request.output_times.back());
  for (double v : read_doubles(f, "/samples/final_state")) {
    if (!std::isfinite(v)) {
      ADD_FAILURE() << "non-finite value in /samples/final_state";
      break;
    }
  }
}

// Per quantity: statistics, nominal run, per-sample reductions; nothing else.
void expect_quantity_datasets(hid_t f, const treedyn::Job& job, const treedyn::EnsembleSpec& spec) {
  const hsize_t T = job.request.output_times.size(), N = spec.runs;
  const hsize_t P = spec.quantiles.size(), B = static_cast<hsize_t>(spec.histogram_bins);
  std::vector<std::string> expected_stats{"/stats/time"}, expected_nominal{"/nominal/time"};
  const treedyn::ColumnLayout layout = treedyn::column_layout(job.model, job.output);
  for (std::size_t iq = 0; iq < layout.quantity.size(); ++iq) {
    const std::string& q = layout.quantity[iq];
    SCOPED_TRACE("quantity " + q);
    const auto& labels = layout.names[iq];
    const hsize_t C = labels.size();
    ASSERT_GT(C, 0u);
    const std::string s = "/stats/" + q + "/";
    for (const char* m : {"count", "mean", "std", "sem", "min", "max"}) {
      EXPECT_EQ(shape(f, s + m), (Dims{T, C})) << m;
      expected_stats.push_back(s + m);
    }
    EXPECT_EQ(read_string_attribute(f, s + "mean", "columns"), labels);
    EXPECT_EQ(shape(f, s + "quantiles"), (Dims{P, T, C}));
    EXPECT_EQ(shape(f, s + "histogram/counts"), (Dims{C, B}));
    EXPECT_EQ(shape(f, s + "histogram/edges"), (Dims{C, B + 1}));
    EXPECT_EQ(shape(f, s + "histogram/underflow"), Dims{C});
    EXPECT_EQ(shape(f, s + "histogram/overflow"), Dims{C});
    for (const char* m :
         {"quantiles", "histogram/counts", "histogram/edges", "histogram/underflow", "histogram/overflow"})
      expected_stats.push_back(s + m);
    EXPECT_EQ(shape(f, "/nominal/" + q), (Dims{T, C}));
    expected_nominal.push_back("/nominal/" + q);
    for (const char* reduction : {"final", "min", "max", "argmin_time", "argmax_time"}) {
      EXPECT_EQ(shape(f, std::string("/samples/") + reduction + "/" + q), (Dims{N, C})) << reduction;
      EXPECT_EQ(read_string_attribute(f, std::string("/samples/") + reduction + "/" + q, "columns"), labels);
    }
    // Every sample is in the statistics of every entry.
    for (long long c : read_integers(f, s + "count")) EXPECT_EQ(c, static_cast<long long>(N));
  }
  std::sort(expected_stats.begin(), expected_stats.end());
  std::sort(expected_nominal.begin(), expected_nominal.end());
  EXPECT_EQ(datasets_under(f, "/stats"), expected_stats);
  EXPECT_EQ(datasets_under(f, "/nominal"), expected_nominal);
  for (const char* reduction : {"final", "min", "max", "argmin_time", "argmax_time"})
    EXPECT_EQ(datasets_under(f, std::string("/samples/") + reduction).size(), job.output.quantities.size());
}

// Named responses: one column each, and their answers.
void expect_response_datasets(hid_t f, const treedyn::EnsembleSpec& spec) {
  const hsize_t N = spec.runs, D = spec.input_dimensions();
  const std::size_t R = spec.responses.size();
  if (R > 0) {
    EXPECT_EQ(shape(f, "/samples/responses"), (Dims{N, R}));
    for (const auto& response : spec.responses) {
      EXPECT_EQ(shape(f, "/responses/" + response.name + "/convergence").at(1), 7u);
      if (response.has_limit()) {
        EXPECT_EQ(shape(f, "/responses/" + response.name + "/exceedance/interval"), Dims{2});
      }
      if (D > 0) {
        EXPECT_EQ(shape(f, "/sensitivity/" + response.name + "/spearman"), Dims{D});
      }
    }
  }
}

TEST_P(EnsembleMpiExample, RunsOnTwoRanksWithEverySampleOkAndTheDocumentedShapes) {
  if (const std::string why = skipped_when_sanitized(GetParam(), false); !why.empty()) GTEST_SKIP() << why;
  const fs::path job_path = fs::path(TREEDYN_JOBS_DIR) / (GetParam() + ".toml");
  // The expected shapes from the job, read by treedyn's own job reader and
  // [ensemble] reader; columns per quantity as `treedyn run` labels them.
  const std::string text = read_text(job_path);
  const treedyn::Job job = treedyn::parse_job(text, job_path.string());
  const treedyn::EnsembleSpec spec = treedyn::read_ensemble(job);
  const hsize_t N = spec.runs, D = spec.input_dimensions();
  ASSERT_GT(N, 0u);
  ASSERT_GT(D, 0u) << "the example's [ensemble] perturbs nothing";

  TempDir dir("ensemble_mpi_example");
  const fs::path out_dir = dir.path() / "out";
  fs::create_directory(out_dir);
  const fs::path output = out_dir / (GetParam() + "_ensemble.h5");
  const auto r = run_ensemble(2, job_path, output, dir.path() / "capture");
  std::printf("[example %s] %llu samples on 2 ranks: exit %d in %.2f s\n", GetParam().c_str(),
              static_cast<unsigned long long>(N), r.exit_code, r.seconds);
  expect_success(r, output);
  EXPECT_EQ(listing(out_dir), std::vector<std::string>{output.filename().string()});
  H5File file(output);
  ASSERT_TRUE(file.ok());
  const hid_t f = file.id();

  EXPECT_EQ(read_integer_attribute(f, "samples"), static_cast<long long>(N));
  EXPECT_EQ(read_integer_attribute(f, "samples_ok"), static_cast<long long>(N));
  EXPECT_EQ(read_integer_attribute(f, "samples_failed"), 0);
  EXPECT_EQ(read_integer_attribute(f, "ranks"), 2);
  EXPECT_EQ(read_integer_attribute(f, "seed"), static_cast<long long>(spec.seed));

  // Times.
  EXPECT_EQ(read_doubles(f, "/stats/time"), job.request.output_times);
  EXPECT_EQ(read_doubles(f, "/nominal/time"), job.request.output_times);

  expect_sample_rows(f, job, spec);
  expect_quantity_datasets(f, job, spec);
  expect_response_datasets(f, spec);
}

std::string job_test_name(const ::testing::TestParamInfo<std::string>& job) { return job.param; }

INSTANTIATE_TEST_SUITE_P(Jobs, EnsembleMpiExample, ::testing::ValuesIn(example_jobs()), job_test_name);

TEST(EnsembleMpiExamples, TheExamplesAreFound) {
  // A moved jobs directory must not turn the parameterised test into nothing.
  EXPECT_GE(example_jobs().size(), 6u) << TREEDYN_JOBS_DIR;
}

}  // namespace
