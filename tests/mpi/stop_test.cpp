// [ensemble.stop] end to end: a run that stops itself at a target precision
// is bitwise the same alone and on 2 and 3 ranks, stops where the rule
// computed here from an unstopped run's responses says it must, and holds
// exactly the prefix of that run's samples. Jobs a stopping rule cannot
// serve are refused.
//
// The case has a known answer (spin_exceedance_job): P(spin0 > 2.19 rad/s)
// = 0.025.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "job/ensemble_spec.hpp"
#include "support/command.hpp"
#include "support/ensemble_run.hpp"
#include "support/hdf5_reader.hpp"

namespace {

using namespace treedyn::testing;
namespace fs = std::filesystem;

constexpr double kLimit = 2.19;
constexpr std::uint64_t kEvery = 100, kMost = 3000;

std::string stop_job(bool with_rule, const std::string& design = "monte_carlo") {
  return spin_exceedance_job(static_cast<int>(kMost), with_rule, design);
}

class Stop : public ::testing::Test {
 protected:
  fs::path write_job(const std::string& name, const std::string& text) {
    const fs::path p = dir_.path() / name;
    write_text(p, text);
    return p;
  }
  TempDir dir_{"stop_test"};
};

TEST_F(Stop, StopsAtTheFirstCheckPointWhereTheTargetHoldsOnAnyRankCount) {
  // The unstopped run, and where the rule must stop on its responses.
  const fs::path full = dir_.path() / "full.h5";
  const auto r = run_ensemble(2, write_job("full.toml", stop_job(false)), full, dir_.path() / "capture_full");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  H5File all(full);
  const std::vector<double> spin = read_doubles(all.id(), "/samples/responses");
  ASSERT_EQ(spin.size(), kMost);
  std::uint64_t expected = 0;
  for (std::uint64_t n = kEvery; n <= kMost && expected == 0; n += kEvery) {
    std::uint64_t k = 0;
    for (std::uint64_t i = 0; i < n; ++i) k += spin[i] > kLimit ? 1 : 0;
    const double p = static_cast<double>(k) / static_cast<double>(n);
    if (k >= treedyn::kMinExceedances && std::sqrt((1.0 - p) / (static_cast<double>(n) * p)) <= 0.2) expected = n;
  }
  ASSERT_GT(expected, 0u) << "the case never reaches its target: it tests nothing";
  ASSERT_LT(expected, kMost);

  const fs::path job = write_job("stop.toml", stop_job(true));
  std::vector<fs::path> outputs;
  // -3: 3 ranks with units of 16 rows (--test-unit-rows): waves of 100 runs
  // hold units and records, and the cut at the stop goes through chunks
  // the senders wrote.
  for (int run : {0, 2, 3, -3}) {
    const int ranks = std::abs(run);
    outputs.push_back(dir_.path() / ("stop" + std::to_string(run) + ".h5"));
    const std::vector<std::string> extra =
        run < 0 ? std::vector<std::string>{"--test-unit-rows", "16"} : std::vector<std::string>{};
    const auto s = run_ensemble(ranks, job, outputs.back(), dir_.path() / ("capture" + std::to_string(run)), extra);
    ASSERT_EQ(s.exit_code, 0) << describe(ranks) << ": " << s.err;
    H5File f(outputs.back());
    EXPECT_EQ(read_integer_attribute(f.id(), "samples_used"), static_cast<long long>(expected)) << describe(ranks);
    EXPECT_EQ(read_integer_attribute(f.id(), "samples"), static_cast<long long>(kMost));
    const std::string reason = read_single_string_attribute(f.id(), "stop_reason");
    EXPECT_NE(reason.find("exceedance_cov of spin0"), std::string::npos) << reason;
    EXPECT_EQ(shape(f.id(), "/samples/status"), std::vector<hsize_t>{expected});
    // The stopped run's samples are the unstopped run's first ones.
    const std::vector<double> kept = read_doubles(f.id(), "/samples/responses");
    EXPECT_EQ(kept, std::vector<double>(spin.begin(), spin.begin() + static_cast<std::ptrdiff_t>(expected)));
    if (run < 0) {
      EXPECT_GT(read_integer_attribute(f.id(), "samples_in_units"), 0) << "no unit was sent";
    }
  }
  H5File alone(outputs[0]);
  for (std::size_t k = 1; k < outputs.size(); ++k) {
    H5File other(outputs[k]);
    expect_identical_datasets(alone.id(), "alone", other.id(), outputs[k].filename().string(),
                              {"/stats", "/samples", "/responses", "/sensitivity"});
  }
}

TEST_F(Stop, CheckPrintsTheRule) {
  const fs::path job = write_job("stop.toml", stop_job(true));
  const auto r = run_command(TREEDYN_ENSEMBLE_BINARY, {job.string(), "--check"}, dir_.path() / "capture_check");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("stop: checked every 100 runs, at the first check point where exceedance_cov of spin0 <= "
                       "0.2 (at most 3000 runs)"),
            std::string::npos)
      << r.out;
}

TEST_F(Stop, JobsARuleCannotServeAreRefused) {
  // A Latin hypercube's first n samples are not a Latin hypercube.
  const fs::path lhs = write_job("lhs.toml", stop_job(true, "latin_hypercube"));
  auto r = run_ensemble(0, lhs, dir_.path() / "lhs.h5", dir_.path() / "capture_lhs");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("lhs.toml:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("ensemble.stop.response: a stopping rule needs a design whose prefixes are designs"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir_.path() / "lhs.h5"));

  // A part of a split ensemble cannot see the samples before it.
  const fs::path job = write_job("stop.toml", stop_job(true));
  r = run_ensemble(2, job, dir_.path() / "part.h5", dir_.path() / "capture_part", {"--samples", "0:100"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("runs as one job"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_.path() / "part.h5"));

  // Targets that name no response, or an exceedance without a limit.
  std::string text = stop_job(false) + "\n[ensemble.stop]\nresponse = \"spin\"\nexceedance_cov = 0.2\nevery = 100\n";
  r = run_ensemble(0, write_job("name.toml", text), dir_.path() / "name.h5", dir_.path() / "capture_name");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("\"spin\" is not the name of an [[ensemble.response]]"), std::string::npos) << r.err;
  text = stop_job(false) + "\n[ensemble.stop]\nresponse = \"spin0\"\nevery = 100\n";
  r = run_ensemble(0, write_job("none.toml", text), dir_.path() / "none.h5", dir_.path() / "capture_none");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("give at least one target"), std::string::npos) << r.err;
  text = stop_job(false) + "\n[ensemble.stop]\nresponse = \"spin0\"\nmean_sem = 0.01\nevery = 5000\n";
  r = run_ensemble(0, write_job("every.toml", text), dir_.path() / "every.h5", dir_.path() / "capture_every");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("ensemble.stop.every: checks every 5000 samples, more than the ensemble makes at most (3000)"),
            std::string::npos)
      << r.err;
}

}  // namespace
