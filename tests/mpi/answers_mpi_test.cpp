// The answers of an ensemble file, end to end: a Saltelli ensemble of a
// branched tree with one response of every kind and stored trajectories, run
// alone and on 1, 2 and 3 ranks. Checks that
//   * /stats, /samples, /responses, /sensitivity and /trajectories are
//     bitwise identical on any number of ranks;
//   * the stored answers equal those recomputed from the file's own /samples;
//   * every response and every per-sample reduction equals a direct
//     computation (written here, not the library's) from the stored
//     trajectory, and the convergence rows are the answers of the prefixes;
//   * `--sample K` and `treedyn run` of `--write-job K` reproduce sample K
//     bit for bit.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "analysis/answers.hpp"
#include "designs/saltelli/saltelli_answer.hpp"
#include "job/ensemble_spec.hpp"
#include "job/job.hpp"
#include "output/quantities.hpp"
#include "support/branched_tree.hpp"
#include "support/command.hpp"
#include "support/ensemble_run.hpp"
#include "support/hdf5_reader.hpp"

namespace {

using namespace treedyn::testing;
namespace fs = std::filesystem;
using namespace treedyn;

// The branched tree of ensemble_mpi_test.cpp, Saltelli's design over its 5
// inputs (N = 8: 56 runs), responses of every kind, 6 stored trajectories.
const std::string kJob = "title = \"answers test: branched 3-body tree\"\n" + kBranchedTreeModel + R"([ensemble]
samples = 8
seed = 42
design = "saltelli"
pilot_samples = 8
block_size = 3
histogram_bins = 16
store_trajectories = 6
bootstrap_resamples = 200

[[ensemble.perturbation]]
target = "body.trunk.orientation"
distribution = "normal"
std = 4.0
unit = "deg"

[[ensemble.perturbation]]
target = "body.bob.mass"
distribution = "uniform"
lower = 0.1
upper = 0.5

[[ensemble.perturbation]]
target = "body.arm.angular_velocity.z"
distribution = "uniform"
lower = 1.0
upper = 3.0

[[ensemble.response]]
name = "peak_angle"
quantity = "joint_angle"
column = "trunk.angle"
reduce = "max"
limit = 3.07
fail_if = "above"

[[ensemble.response]]
name = "lowest_bob"
quantity = "com_position"
column = "bob.z"
reduce = "min"

[[ensemble.response]]
name = "final_energy"
quantity = "energy"
column = "kinetic"
reduce = "final"

[[ensemble.response]]
name = "mean_spin"
quantity = "angular_velocity"
column = "arm.z"
reduce = "mean"

[[ensemble.response]]
name = "rms_sway"
quantity = "com_position"
column = "bob.y"
reduce = "rms"

[[ensemble.response]]
name = "angle_between_outputs"
quantity = "joint_angle"
column = "trunk.angle"
reduce = "at_time"
time = 1.2345

[[ensemble.response]]
name = "first_over"
quantity = "joint_angle"
column = "trunk.angle"
reduce = "first_time_above"
threshold = 0.54

[[ensemble.response]]
name = "first_under"
quantity = "joint_angle"
column = "trunk.angle"
reduce = "first_time_below"
threshold = 0.2
limit = 1.5
fail_if = "below"
)";

constexpr std::size_t kBase = 8, kInputs = 5, kRuns = kBase * (kInputs + 2), kStored = 6;
const std::vector<int> kRanks = {0, 1, 2, 3};  // 0: the binary without mpirun

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// The ensemble runs once (the binary alone) for the tests of this file
// (ctest runs each test in its own process); the rank comparison runs the rest.
class Answers : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<TempDir>("answers_mpi_test");
    job_ = dir_->path() / "tree.toml";
    write_text(job_, kJob);
    fs::create_directory(dir_->path() / "capture");
    run(0);
  }
  static void run(int ranks) {
    const fs::path out = dir_->path() / ("ensemble_" + std::to_string(ranks) + ".h5");
    results_.push_back(run_ensemble(ranks, job_, out, dir_->path() / "capture"));
    std::printf("[answers] %s: exit %d in %.2f s\n", describe(ranks).c_str(), results_.back().exit_code,
                results_.back().seconds);
    outputs_.push_back(out);
  }
  static void TearDownTestSuite() { dir_.reset(); }

  static const fs::path& output(std::size_t i = 0) { return outputs_[i]; }
  static treedyn::Job job() { return treedyn::read_job(job_); }

  static std::unique_ptr<TempDir> dir_;
  static fs::path job_;
  static std::vector<fs::path> outputs_;
  static std::vector<CommandResult> results_;
};
std::unique_ptr<TempDir> Answers::dir_;
fs::path Answers::job_;
std::vector<fs::path> Answers::outputs_;
std::vector<CommandResult> Answers::results_;

TEST_F(Answers, RunsAndSaysHowManyRuns) {
  EXPECT_EQ(results_[0].exit_code, 0) << results_[0].err;
  H5File f(output());
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(read_integer_attribute(f.id(), "samples"), static_cast<long long>(kRuns));
  EXPECT_EQ(read_integer_attribute(f.id(), "samples_ok"), static_cast<long long>(kRuns));
  const CommandResult check =
      run_command(TREEDYN_ENSEMBLE_BINARY, {"--check", job_.string()}, dir_->path() / "capture");
  EXPECT_EQ(check.exit_code, 0) << check.err;
  EXPECT_NE(check.out.find("N (D + 2) = 8 x 7 = 56 runs"), std::string::npos) << check.out;
  EXPECT_NE(check.out.find("response first_under: first_time_below of joint_angle trunk.angle"), std::string::npos)
      << check.out;
}

TEST_F(Answers, SameBitsAloneAndOnOneTwoAndThreeRanks) {
  for (std::size_t i = 1; i < kRanks.size(); ++i) {
    run(kRanks[i]);
    ASSERT_EQ(results_[i].exit_code, 0) << results_[i].err;
  }
  H5File reference(output(0));
  ASSERT_TRUE(reference.ok());
  for (std::size_t i = 1; i < kRanks.size(); ++i) {
    SCOPED_TRACE(describe(kRanks[i]));
    H5File f(output(i));
    ASSERT_TRUE(f.ok());
    expect_identical_datasets(
        reference.id(), describe(kRanks[0]), f.id(), describe(kRanks[i]),
        {"/stats", "/samples", "/responses", "/sensitivity", "/trajectories", "/integration_check"});
  }
}

// The answers are a pure function of /samples: recomputing them from the
// file's own status, inputs and responses gives the stored bits.
TEST_F(Answers, StoredAnswersEqualThoseRecomputedFromTheSamples) {
  const treedyn::Job j = job();
  const EnsembleSpec spec = read_ensemble(j);
  H5File file(output());
  ASSERT_TRUE(file.ok());
  const hid_t f = file.id();
  std::vector<std::int32_t> status;
  for (long long s : read_integers(f, "/samples/status")) status.push_back(static_cast<std::int32_t>(s));
  const ensemble::ResponseTable table(status, read_doubles(f, "/samples/inputs"), read_doubles(f, "/samples/responses"),
                                      kInputs, spec.responses.size());
  const std::vector<analysis::ResponseAnswer> answers = analysis::answer_responses(spec, table);
  ASSERT_EQ(answers.size(), 8u);
  auto expect_bits = [](const std::vector<double>& stored, const std::vector<double>& computed,
                        const std::string& what) {
    ASSERT_EQ(stored.size(), computed.size()) << what;
    for (std::size_t k = 0; k < stored.size(); ++k)
      EXPECT_TRUE(same_bits(stored[k], computed[k]) || (std::isnan(stored[k]) && std::isnan(computed[k])))
          << what << "[" << k << "]: stored " << stored[k] << ", recomputed " << computed[k];
  };
  for (std::size_t r = 0; r < answers.size(); ++r) {
    const std::string g = "/responses/" + spec.responses[r].name;
    SCOPED_TRACE(g);
    const analysis::ResponseAnswer& a = answers[r];
    expect_bits(read_doubles(f, g + "/mean"), {a.mean}, "mean");
    expect_bits(read_doubles(f, g + "/sem"), {a.sem}, "sem");
    EXPECT_EQ(read_integers(f, g + "/used"), std::vector<long long>{static_cast<long long>(a.used)});
    std::vector<double> convergence;
    for (const auto& p : a.convergence)
      convergence.insert(convergence.end(), {static_cast<double>(p.samples), static_cast<double>(p.used), p.mean, p.sem,
                                             p.probability, p.interval.low, p.interval.high});
    expect_bits(read_doubles(f, g + "/convergence"), convergence, "convergence");
    if (a.exceedance) {
      expect_bits(read_doubles(f, g + "/exceedance/probability"), {a.exceedance->probability}, "probability");
      expect_bits(read_doubles(f, g + "/exceedance/interval"),
                  {a.exceedance->interval.low, a.exceedance->interval.high}, "interval");
      EXPECT_EQ(read_integers(f, g + "/exceedance/count"),
                std::vector<long long>{static_cast<long long>(a.exceedance->exceeded)});
    }
    const std::string s = "/sensitivity/" + spec.responses[r].name;
    expect_bits(read_doubles(f, s + "/spearman"), a.ranks.spearman, "spearman");
    expect_bits(read_doubles(f, s + "/srrc"), a.ranks.srrc, "srrc");
    const auto* saltelli = analysis::design_answer_as<treedyn::designs::SaltelliAnswer>(a);
    ASSERT_NE(saltelli, nullptr);
    expect_bits(read_doubles(f, s + "/first_order"), saltelli->indices.first, "first_order");
    expect_bits(read_doubles(f, s + "/total_order"), saltelli->indices.total, "total_order");
    expect_bits(read_doubles(f, s + "/first_order_ci"), saltelli->indices.first_ci, "first_order_ci");
    expect_bits(read_doubles(f, s + "/total_order_ci"), saltelli->indices.total_ci, "total_order_ci");
  }
  // Not vacuous: the indices are numbers, and both limit states have
  // samples on either side.
  for (double v : read_doubles(f, "/sensitivity/peak_angle/total_order")) EXPECT_TRUE(std::isfinite(v));
  for (const char* name : {"peak_angle", "first_under"}) {
    const double p = read_doubles(f, std::string("/responses/") + name + "/exceedance/probability").at(0);
    EXPECT_GT(p, 0.0) << name;
    EXPECT_LT(p, 1.0) << name;
  }
}

// Independent reductions of one column x(t) at the output times t.
double direct(const std::string& reduce, const std::vector<double>& x, const std::vector<double>& t, double parameter) {
  if (reduce == "final") return x.back();
  if (reduce == "min") return *std::min_element(x.begin(), x.end());
  if (reduce == "max") return *std::max_element(x.begin(), x.end());
  if (reduce == "mean" || reduce == "rms") {
    long double s = 0.0L;
    for (double v : x) s += reduce == "mean" ? v : static_cast<long double>(v) * v;
    const double m = static_cast<double>(s / static_cast<long double>(x.size()));
    return reduce == "mean" ? m : std::sqrt(m);
  }
  if (reduce == "at_time") {
    for (std::size_t k = 1; k < t.size(); ++k)
      if (t[k] >= parameter) return x[k - 1] + (x[k] - x[k - 1]) * (parameter - t[k - 1]) / (t[k] - t[k - 1]);
  }
  const bool above = reduce == "first_time_above";
  for (std::size_t k = 0; k < t.size(); ++k) {
    const bool beyond = above ? x[k] > parameter : x[k] < parameter;
    if (!beyond) continue;
    if (k == 0) return t[0];
    return t[k - 1] + (t[k] - t[k - 1]) * (parameter - x[k - 1]) / (x[k] - x[k - 1]);
  }
  return std::numeric_limits<double>::infinity();
}

TEST_F(Answers, EveryResponseAndReductionMatchesTheStoredTrajectory) {
  const treedyn::Job j = job();
  const EnsembleSpec spec = read_ensemble(j);
  const treedyn::ColumnLayout layout = treedyn::column_layout(j.model, j.output);
  H5File file(output());
  ASSERT_TRUE(file.ok());
  const hid_t f = file.id();
  const std::vector<double>& t = j.request.output_times;
  const std::size_t T = t.size(), R = spec.responses.size();
  const std::vector<double> responses = read_doubles(f, "/samples/responses");
  ASSERT_EQ(responses.size(), kRuns * R);
  std::size_t infinite = 0, finite_crossings = 0;
  for (std::size_t q = 0; q < layout.quantity.size(); ++q) {
    const std::string& name = layout.quantity[q];
    const std::size_t C = layout.names[q].size();
    const std::vector<double> stored = read_doubles(f, "/trajectories/" + name);
    ASSERT_EQ(shape(f, "/trajectories/" + name), (std::vector<hsize_t>{kStored, T, C}));
    const auto finals = read_doubles(f, "/samples/final/" + name), mins = read_doubles(f, "/samples/min/" + name),
               maxs = read_doubles(f, "/samples/max/" + name), argmin = read_doubles(f, "/samples/argmin_time/" + name),
               argmax = read_doubles(f, "/samples/argmax_time/" + name);
    for (std::size_t k = 0; k < kStored; ++k)
      for (std::size_t c = 0; c < C; ++c) {
        std::vector<double> x(T);
        for (std::size_t i = 0; i < T; ++i) x[i] = stored[(k * T + i) * C + c];
        const std::size_t e = k * C + c;
        EXPECT_EQ(finals[e], x.back()) << name << " " << k << " " << c;
        const auto lo = std::min_element(x.begin(), x.end()), hi = std::max_element(x.begin(), x.end());
        EXPECT_EQ(mins[e], *lo);
        EXPECT_EQ(maxs[e], *hi);
        EXPECT_EQ(argmin[e], t[static_cast<std::size_t>(lo - x.begin())]);
        EXPECT_EQ(argmax[e], t[static_cast<std::size_t>(hi - x.begin())]);
      }
    for (std::size_t r = 0; r < R; ++r) {
      const Response& response = spec.responses[r];
      if (response.quantity != name) continue;
      const auto c = static_cast<std::size_t>(
          std::find(layout.names[q].begin(), layout.names[q].end(), response.column) - layout.names[q].begin());
      const std::string reduce(treedyn::name(response.reduce));
      const double parameter = reduce == "at_time" ? response.time : response.threshold;
      for (std::size_t k = 0; k < kStored; ++k) {
        std::vector<double> x(T);
        for (std::size_t i = 0; i < T; ++i) x[i] = stored[(k * T + i) * C + c];
        const double expected = direct(reduce, x, t, parameter), got = responses[k * R + r];
        SCOPED_TRACE(response.name + " sample " + std::to_string(k));
        if (std::isinf(expected)) {
          ++infinite;
          EXPECT_EQ(got, expected);
        } else {
          if (reduce.rfind("first_time", 0) == 0) ++finite_crossings;
          // Sums in another order (long double here): 1e-13 relative.
          EXPECT_NEAR(got, expected, 1e-13 * std::max(1.0, std::abs(expected)));
        }
      }
    }
  }
  // Both outcomes of a crossing were exercised.
  EXPECT_GT(infinite, 0u);
  EXPECT_GT(finite_crossings, 0u);
}

// Convergence row m: the mean, standard error and exceedance of samples
// 0 .. m-1 (their A and B runs), recomputed here by two passes.
TEST_F(Answers, ConvergenceRowsAreTheAnswersOfThePrefixes) {
  const treedyn::Job j = job();
  const EnsembleSpec spec = read_ensemble(j);
  H5File file(output());
  ASSERT_TRUE(file.ok());
  const std::vector<double> responses = read_doubles(file.id(), "/samples/responses");
  const std::size_t R = spec.responses.size();
  for (std::size_t r = 0; r < R; ++r) {
    const Response& response = spec.responses[r];
    SCOPED_TRACE(response.name);
    const std::vector<double> rows = read_doubles(file.id(), "/responses/" + response.name + "/convergence");
    // Saltelli: whole blocks of D + 2 = 7 runs, 1, 2, 4, 8 of them.
    const std::vector<std::size_t> counts = {7, 14, 28, kRuns};
    ASSERT_EQ(rows.size(), counts.size() * 7);
    for (std::size_t i = 0; i < counts.size(); ++i) {
      const std::size_t m = counts[i];
      std::vector<double> used;
      std::size_t exceeded = 0;
      std::size_t draws = 0;
      for (std::size_t k = 0; k < m; ++k) {
        // Saltelli: the A and B runs (r = 0, 1 of each block of D + 2) only.
        if (k % (kInputs + 2) >= 2) continue;
        ++draws;
        const double v = responses[k * R + r];
        if (std::isfinite(v)) used.push_back(v);
        if (response.has_limit() &&
            (response.fail_if == Response::FailIf::above ? v > response.limit : v < response.limit))
          ++exceeded;
      }
      EXPECT_EQ(rows[i * 7 + 0], static_cast<double>(m));
      EXPECT_EQ(rows[i * 7 + 1], static_cast<double>(used.size()));
      if (used.size() > 1) {
        double mean = 0.0;
        for (double v : used) mean += v;
        mean /= static_cast<double>(used.size());
        double ss = 0.0;
        for (double v : used) ss += (v - mean) * (v - mean);
        const double sem = std::sqrt(ss / static_cast<double>(used.size() - 1) / static_cast<double>(used.size()));
        EXPECT_NEAR(rows[i * 7 + 2], mean, 1e-12 * std::max(1.0, std::abs(mean))) << "m = " << m;
        EXPECT_NEAR(rows[i * 7 + 3], sem, 1e-9 * std::max(1e-3, sem)) << "m = " << m;
      }
      if (response.has_limit())
        EXPECT_EQ(rows[i * 7 + 4], static_cast<double>(exceeded) / static_cast<double>(draws)) << "m = " << m;
      else
        EXPECT_TRUE(std::isnan(rows[i * 7 + 4]));
    }
  }
}

// Sample K alone: its trajectory is the stored one and its final state the
// ensemble's, bit for bit.
TEST_F(Answers, SampleRerunAloneIsBitwiseTheEnsembleSample) {
  H5File ensemble(output());
  ASSERT_TRUE(ensemble.ok());
  const treedyn::Job j = job();
  const treedyn::ColumnLayout layout = treedyn::column_layout(j.model, j.output);
  const std::size_t T = j.request.output_times.size(), n = 3;
  const std::vector<double> finals = read_doubles(ensemble.id(), "/samples/final_state");
  const std::vector<double> inputs = read_doubles(ensemble.id(), "/samples/inputs");
  const std::vector<double> reached = read_doubles(ensemble.id(), "/samples/time_reached");
  for (std::size_t k : {std::size_t{3}, std::size_t{5}, kRuns - 1}) {
    SCOPED_TRACE("sample " + std::to_string(k));
    const fs::path out = dir_->path() / ("sample_" + std::to_string(k) + ".h5");
    const CommandResult r =
        run_command(TREEDYN_ENSEMBLE_BINARY, {job_.string(), "--sample", std::to_string(k), "-o", out.string(), "-q"},
                    dir_->path() / "capture");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    H5File sample(out);
    ASSERT_TRUE(sample.ok());
    const std::vector<double> final_state = read_doubles(sample.id(), "/final_state");
    ASSERT_EQ(final_state.size(), 7 * n);
    for (std::size_t i = 0; i < 7 * n; ++i) EXPECT_TRUE(same_bits(final_state[i], finals[k * 7 * n + i])) << i;
    const std::vector<double> mine = read_doubles(sample.id(), "/sample/inputs");
    ASSERT_EQ(mine.size(), kInputs);
    for (std::size_t i = 0; i < kInputs; ++i) EXPECT_TRUE(same_bits(mine[i], inputs[k * kInputs + i]));
    // The /sample attributes say what /samples says of it (time_reached was
    // once 0 for every successful rerun).
    const Hid group(H5Gopen2(sample.id(), "/sample", H5P_DEFAULT), H5Gclose);
    ASSERT_TRUE(group.ok());
    EXPECT_EQ(read_integer_attribute(group.get(), "index"), static_cast<long long>(k));
    EXPECT_EQ(read_integer_attribute(group.get(), "status"), 0);
    const std::vector<double> time_reached = read_double_attribute(group.get(), "time_reached");
    ASSERT_EQ(time_reached.size(), 1u);
    EXPECT_TRUE(same_bits(time_reached[0], reached[k])) << time_reached[0] << " vs " << reached[k];
    EXPECT_EQ(time_reached[0], j.request.output_times.back());
    if (k >= kStored) continue;
    for (std::size_t q = 0; q < layout.quantity.size(); ++q) {
      const std::vector<double> stored = read_doubles(ensemble.id(), "/trajectories/" + layout.quantity[q]);
      const std::vector<double> alone = read_doubles(sample.id(), layout.quantity[q]);
      const std::size_t C = layout.names[q].size();
      ASSERT_EQ(alone.size(), T * C);
      EXPECT_EQ(0, std::memcmp(alone.data(), stored.data() + k * T * C, T * C * sizeof(double))) << layout.quantity[q];
    }
  }
}

// The written job, run by `treedyn run`, reproduces the sample bitwise.
TEST_F(Answers, WrittenJobOfSampleKReproducesItWithTreedynRun) {
  H5File ensemble(output());
  ASSERT_TRUE(ensemble.ok());
  const std::vector<double> finals = read_doubles(ensemble.id(), "/samples/final_state");
  const std::size_t n = 3;
  for (std::size_t k : {std::size_t{2}, std::size_t{4}, std::size_t{30}}) {  // B_0, AB_2,0, AB_ of block 4
    SCOPED_TRACE("sample " + std::to_string(k));
    const fs::path written = dir_->path() / ("sample_" + std::to_string(k) + ".toml");
    const CommandResult w =
        run_command(TREEDYN_ENSEMBLE_BINARY, {job_.string(), "--write-job", std::to_string(k), "-o", written.string()},
                    dir_->path() / "capture");
    ASSERT_EQ(w.exit_code, 0) << w.err;
    const std::string text = read_text(written);
    EXPECT_EQ(text.find("[ensemble]"), std::string::npos) << text;
    EXPECT_NE(text.find("[sample]\nindex = " + std::to_string(k)), std::string::npos) << text;
    const fs::path out = dir_->path() / ("rerun_" + std::to_string(k) + ".h5");
    const CommandResult r =
        run_command(TREEDYN_BINARY, {"run", written.string(), "-o", out.string(), "-q"}, dir_->path() / "capture");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    H5File rerun(out);
    ASSERT_TRUE(rerun.ok());
    const std::vector<double> final_state = read_doubles(rerun.id(), "/final_state");
    ASSERT_EQ(final_state.size(), 7 * n);
    for (std::size_t i = 0; i < 7 * n; ++i)
      EXPECT_TRUE(same_bits(final_state[i], finals[k * 7 * n + i]))
          << i << ": " << final_state[i] << " vs " << finals[k * 7 * n + i];
    // A sample job is not written from a sample job.
    const CommandResult again = run_command(
        TREEDYN_ENSEMBLE_BINARY, {written.string(), "--write-job", "0", "-o", (dir_->path() / "x.toml").string()},
        dir_->path() / "capture");
    EXPECT_EQ(again.exit_code, 2);
  }
}

TEST_F(Answers, SampleOutsideTheEnsembleIsBadInput) {
  const CommandResult r =
      run_command(TREEDYN_ENSEMBLE_BINARY,
                  {job_.string(), "--sample", std::to_string(kRuns), "-o", (dir_->path() / "no.h5").string()},
                  dir_->path() / "capture");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("there is no sample 56: the ensemble has 56 samples, 0 .. 55"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_->path() / "no.h5"));
}

}  // namespace
