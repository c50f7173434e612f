// Subset simulation through the tree dynamics, against an exceedance
// probability known exactly from a conserved quantity.
//
// The case: one body on a spherical joint under gravity whose inertia about
// the pivot is isotropic, J_O = 0.55 E (J_c = diag(0.3, 0.3, 0.55) kg m^2,
// 1 kg, pivot 0.5 m above the centre of mass), started hanging at rest in
// orientation with an angular velocity w ~ N(0, I) rad/s (three sampled
// inputs). Its total energy is conserved, E = E0 + J_O |w|^2 / 2 with
// E0 = -m g d = -4.905 J, and |w|^2 is chi-square with 3 degrees of
// freedom, so P(E > E0 + 0.275 c) = Q_chi2(3, c) exactly: the limit is set
// from c = 2 gamma_q_inv(3/2, P). The integrator keeps E to ~1e-10 J, far
// inside any difference that matters here.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "support/command.hpp"
#include "support/ensemble_run.hpp"
#include "support/hdf5_reader.hpp"

namespace {

using namespace treedyn::testing;
namespace fs = std::filesystem;

const std::string kSubset = kBallSubset;

struct RareEvent {
  double probability = 0, cov = 0;
  long long runs = 0, rows = 0;
};

RareEvent rare_event_of(const fs::path& file) {
  H5File f(file);
  RareEvent r;
  r.probability = read_doubles(f.id(), "/rare_event/energy/probability").at(0);
  r.cov = read_doubles(f.id(), "/rare_event/energy/cov").at(0);
  r.runs = read_integers(f.id(), "/rare_event/energy/runs").at(0);
  r.rows = static_cast<long long>(shape(f.id(), "/samples/status").at(0));
  return r;
}

class Subset : public ::testing::Test {
 protected:
  fs::path write_job(const std::string& name, const std::string& text) {
    const fs::path p = dir_.path() / name;
    write_text(p, text);
    return p;
  }
  TempDir dir_{"subset_test"};
};

TEST_F(Subset, OneInAThousandIsExactWithinItsCovOnAnyRankCount) {
  const double exact = 1e-3;
  const fs::path job = write_job("ball.toml", isotropic_ball_job(ball_limit_for(exact), 1000, kSubset));
  std::vector<fs::path> outputs;
  for (int ranks : {0, 2, 3}) {
    outputs.push_back(dir_.path() / ("ball" + std::to_string(ranks) + ".h5"));
    const auto r = run_ensemble(ranks, job, outputs.back(), dir_.path() / ("capture" + std::to_string(ranks)));
    ASSERT_EQ(r.exit_code, 0) << describe(ranks) << ": " << r.err;
  }
  const RareEvent r = rare_event_of(outputs[0]);
  std::printf("P = %.4g (exact %.4g), cov %.3f, %lld runs\n", r.probability, exact, r.cov, r.runs);
  EXPECT_LE(std::abs(r.probability - exact), 2.0 * r.cov * r.probability);
  EXPECT_EQ(r.rows, r.runs) << "every run is a row of /samples";
  H5File f(outputs[0]);
  EXPECT_NEAR(read_double_array(f.id(), "/nominal/energy")(0, 3), kBallE0, 1e-12) << "the case's E0";
  // Levels 0 .. m: N (1 + (1 - p0) m) runs; each row's place by the index.
  const std::vector<long long> level = read_integers(f.id(), "/samples/level"),
                               chain = read_integers(f.id(), "/samples/chain"),
                               state = read_integers(f.id(), "/samples/state");
  const long long m = level.back();
  EXPECT_EQ(r.runs, 1000 + m * 900);
  for (long long k = 0; k < r.rows; k += 97) {
    const long long within = k < 1000 ? k : (k - 1000) % 900;
    EXPECT_EQ(level[k], k < 1000 ? 0 : 1 + (k - 1000) / 900) << k;
    EXPECT_EQ(chain[k], k < 1000 ? k : within / 9) << k;
    EXPECT_EQ(state[k], k < 1000 ? 0 : 1 + within % 9) << k;
  }
  // /stats is level 0, the Monte-Carlo sample.
  EXPECT_EQ(read_double_array(f.id(), "/stats/energy/count")(0, 3), 1000.0);
  for (std::size_t k = 1; k < outputs.size(); ++k) {
    H5File other(outputs[k]);
    expect_identical_datasets(f.id(), "alone", other.id(), outputs[k].filename().string(),
                              {"/stats", "/samples", "/responses", "/rare_event"});
  }
  // The report answers first: the probability with its cov, the levels, the
  // runs beside crude Monte Carlo's.
  const fs::path report = dir_.path() / "report";
  const auto page = run_command(TREEDYN_BINARY, {"report", outputs[0].string(), "-o", report.string()},
                                dir_.path() / "capture_report");
  ASSERT_EQ(page.exit_code, 0) << page.err;
  const std::string html = read_text(report / "index.html"), summary = read_text(report / "summary.txt");
  EXPECT_LT(html.find("Rare event (subset simulation)"), html.find("<h2>energy</h2>")) << "the answer comes first";
  EXPECT_NE(summary.find("subset simulation: P(energy > "), std::string::npos) << summary;
  EXPECT_NE(summary.find("crude Monte Carlo would need about"), std::string::npos) << summary;
  EXPECT_NE(summary.find("ensemble: " + std::to_string(r.runs) + " samples"), std::string::npos) << summary;
}

// Any run of any level alone: --sample K --from the ensemble file replays
// the levels to K's inputs; its final state is the ensemble's, bit for bit.
TEST_F(Subset, ARunOfALaterLevelRerunsAloneBitForBit) {
  const fs::path job = write_job("ball.toml", isotropic_ball_job(ball_limit_for(1e-3), 500, kSubset));
  const fs::path out = dir_.path() / "ball.h5";
  ASSERT_EQ(run_ensemble(2, job, out, dir_.path() / "capture").exit_code, 0);
  H5File f(out);
  const DoubleArray final_state = read_double_array(f.id(), "/samples/final_state");
  const long long rows = static_cast<long long>(final_state.rows());
  for (long long k : {7LL, 500LL + 3 * 9 + 4, rows - 1}) {
    const fs::path alone = dir_.path() / ("sample" + std::to_string(k) + ".h5");
    const auto r =
        run_command(TREEDYN_ENSEMBLE_BINARY,
                    {job.string(), "--sample", std::to_string(k), "--from", out.string(), "-o", alone.string(), "-q"},
                    dir_.path() / "capture_sample");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    H5File a(alone);
    const std::vector<double> mine = read_doubles(a.id(), "/final_state");
    for (std::size_t c = 0; c < mine.size(); ++c) EXPECT_EQ(mine[c], final_state(static_cast<std::size_t>(k), c)) << k;
  }
  // --write-job K --from the file: `treedyn run` of that job is run K too.
  const long long k = 500 + 7 * 9 + 2;
  const fs::path sample_job = dir_.path() / "sample.toml", sample_out = dir_.path() / "sample_job.h5";
  ASSERT_EQ(
      run_command(TREEDYN_ENSEMBLE_BINARY,
                  {job.string(), "--write-job", std::to_string(k), "--from", out.string(), "-o", sample_job.string()},
                  dir_.path() / "capture_write")
          .exit_code,
      0);
  ASSERT_EQ(run_command(TREEDYN_BINARY, {"run", sample_job.string(), "-o", sample_out.string(), "-q"},
                        dir_.path() / "capture_run")
                .exit_code,
            0);
  H5File written(sample_out);
  const std::vector<double> from_job = read_doubles(written.id(), "/final_state");
  for (std::size_t c = 0; c < from_job.size(); ++c)
    EXPECT_EQ(from_job[c], final_state(static_cast<std::size_t>(k), c)) << "--write-job " << k;
  const std::vector<std::string> stats_about = read_string_attribute(f.id(), "/stats", "description");
  ASSERT_EQ(stats_about.size(), 1u);
  EXPECT_NE(stats_about[0].find("subset_simulation: level 0 alone"), std::string::npos) << stats_about[0];
  const auto refused =
      run_command(TREEDYN_ENSEMBLE_BINARY,
                  {job.string(), "--sample", std::to_string(rows - 1), "-o", (dir_.path() / "no.h5").string(), "-q"},
                  dir_.path() / "capture_refused");
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("give the ensemble's output file with --from FILE.h5"), std::string::npos) << refused.err;
  EXPECT_FALSE(fs::exists(dir_.path() / "no.h5"));
}

// The same exceedance by crude Monte Carlo with 30 times the runs: its
// Wilson interval holds the exact value, and subset simulation's estimate
// agrees with it within two combined standard errors.
TEST_F(Subset, CrudeMonteCarloWithThirtyTimesTheRunsAgrees) {
  if (const std::string why = skipped_when_sanitized_as_large("crude Monte Carlo (111,000 runs)"); !why.empty())
    GTEST_SKIP() << why;
  const double exact = 1e-3;
  const fs::path subset = write_job("subset.toml", isotropic_ball_job(ball_limit_for(exact), 1000, kSubset));
  ASSERT_EQ(run_ensemble(2, subset, dir_.path() / "subset.h5", dir_.path() / "capture_s").exit_code, 0);
  const RareEvent r = rare_event_of(dir_.path() / "subset.h5");
  const fs::path crude =
      write_job("crude.toml",
                isotropic_ball_job(ball_limit_for(exact), static_cast<int>(30 * r.runs), "design = \"monte_carlo\""));
  const auto c = run_ensemble(2, crude, dir_.path() / "crude.h5", dir_.path() / "capture_c");
  ASSERT_EQ(c.exit_code, 0) << c.err;
  H5File f(dir_.path() / "crude.h5");
  const double p = read_doubles(f.id(), "/responses/energy/exceedance/probability").at(0);
  const std::vector<double> wilson = read_doubles(f.id(), "/responses/energy/exceedance/interval");
  std::printf("crude Monte Carlo, %lld runs: P = %.4g [%.4g, %.4g]; subset simulation, %lld runs: %.4g (cov %.3f)\n",
              30 * r.runs, p, wilson[0], wilson[1], r.runs, r.probability, r.cov);
  EXPECT_LE(wilson[0], exact);
  EXPECT_GE(wilson[1], exact);
  const double crude_se = std::sqrt(p * (1.0 - p) / static_cast<double>(30 * r.runs));
  EXPECT_LE(std::abs(r.probability - p), 2.0 * std::hypot(r.cov * r.probability, crude_se));
}

// One in a million: a coefficient of variation of at most 0.15 with at most
// 50,000 runs (N = 7000 per level), and the estimate within two of it.
TEST_F(Subset, OneInAMillionWithinFiftyThousandRuns) {
  if (const std::string why = skipped_when_sanitized_as_large("P = 1e-6 (38,500 runs)"); !why.empty())
    GTEST_SKIP() << why;
  const double exact = 1e-6;
  const fs::path job =
      write_job("million.toml", isotropic_ball_job(ball_limit_for(exact), 7000, kSubset + "\nmax_levels = 8"));
  const auto run = run_ensemble(2, job, dir_.path() / "million.h5", dir_.path() / "capture");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const RareEvent r = rare_event_of(dir_.path() / "million.h5");
  std::printf("P = %.4g (exact %.4g), cov %.3f, %lld runs\n", r.probability, exact, r.cov, r.runs);
  EXPECT_LE(r.cov, 0.15);
  EXPECT_LE(r.runs, 50000);
  EXPECT_LE(std::abs(r.probability - exact), 2.0 * r.cov * r.probability);
}

TEST_F(Subset, JobsItCannotServeAreRefused) {
  struct Case {
    std::string what, text, message;
  };
  const double b = ball_limit_for(1e-3);
  // (2^64 + 2) / 3 samples per level make 2 runs in all once multiplied
  // out modulo 2^64 (p0 = 1/2, 4 levels): refused for the samples alone.
  std::string huge = isotropic_ball_job(b, 1000, kSubset + "\nlevel_probability = 0.5\nmax_levels = 4");
  huge.replace(huge.find("samples = 1000"), 14, "samples = 6148914691236517206");
  const std::vector<Case> cases = {
      {"huge", huge, "ensemble.samples: 6148914691236517206 samples: at most 67108864"},
      {"no table", isotropic_ball_job(b, 1000, "design = \"subset_simulation\""),
       "ensemble.design: subset_simulation needs an [ensemble.subset] table"},
      {"chains", isotropic_ball_job(b, 1005, kSubset), "samples must be a multiple of 10"},
      {"p0", isotropic_ball_job(b, 1000, kSubset + "\nlevel_probability = 0.3"),
       "1 / level_probability must be a whole number"},
      {"other design",
       isotropic_ball_job(b, 1000, "design = \"monte_carlo\"\n\n[ensemble.subset]\nresponse = \"energy\""),
       "[ensemble.subset] is only for design = \"subset_simulation\""},
      {"no limit",
       isotropic_ball_job(b, 1000, "design = \"subset_simulation\"\n\n[ensemble.subset]\nresponse = \"energy\"") +
           "\n[[ensemble.response]]\nname = \"free\"\nquantity = \"energy\"\ncolumn = \"kinetic\"\nreduce = \"max\"\n",
       ""},
  };
  for (const Case& c : cases) {
    std::string text = c.text;
    if (c.what == "no limit") {
      const std::size_t at = text.find("response = \"energy\"");
      text.replace(at, 19, "response = \"free\"");
    }
    const fs::path job = write_job(c.what + ".toml", text);
    const auto r = run_ensemble(0, job, dir_.path() / "refused.h5", dir_.path() / "capture_refused");
    EXPECT_EQ(r.exit_code, 2) << c.what << ": " << r.err;
    const std::string message = c.what == "no limit" ? "has no limit" : c.message;
    EXPECT_NE(r.err.find(message), std::string::npos) << c.what << ": " << r.err;
    EXPECT_NE(r.err.find(c.what + ".toml:"), std::string::npos) << c.what << ": " << r.err;
    EXPECT_FALSE(fs::exists(dir_.path() / "refused.h5"));
  }
}

}  // namespace

namespace {

// The shipped rare-event example (jobs/rare_events/), shortened: 10 s of
// motion, 100 runs per level, two levels after level 0.
TEST(SubsetExample, TheCraneJobRunsAsShippedAndShortened) {
  if (const std::string why = skipped_when_sanitized("crane_payload", false); !why.empty()) GTEST_SKIP() << why;
  TempDir dir("subset_example");
  const fs::path shipped = fs::path(TREEDYN_JOBS_DIR) / "rare_events" / "crane_peak_tension.toml";
  const auto check = run_command(TREEDYN_ENSEMBLE_BINARY, {shipped.string(), "--check"}, dir.path() / "capture_check");
  ASSERT_EQ(check.exit_code, 0) << check.err;
  EXPECT_NE(check.out.find("subset_simulation: 1000 runs per level"), std::string::npos) << check.out;
  std::string text = read_text(shipped);
  for (const auto& [from, to] :
       std::vector<std::pair<std::string, std::string>>{{"end_time = 60.0", "end_time = 10.0"},
                                                        {"samples = 1000 ", "samples = 100 "},
                                                        {"max_levels = 8", "max_levels = 2"}}) {
    const std::size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << "the example changed: " << from;
    text.replace(at, from.size(), to);
  }
  const fs::path job = dir.path() / "crane.toml";
  write_text(job, text);
  const auto r = run_ensemble(2, job, dir.path() / "crane.h5", dir.path() / "capture");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  H5File f(dir.path() / "crane.h5");
  EXPECT_TRUE(exists(f.id(), "/rare_event/peak_tension/probability"));
  EXPECT_EQ(read_integers(f.id(), "/rare_event/peak_tension/runs").at(0),
            static_cast<long long>(shape(f.id(), "/samples/status").at(0)));
}

// The former rare-event example, whose probability is set by the container
// mass's truncation at 2500 kg (tests/support/crane_truncated_mass.toml):
// the failure region finds the runs beyond the limit at that bound, and the
// summary warns that P depends on where the distribution is cut off.
TEST(SubsetExample, ATruncationBoundThatSetsPIsFoundAndWarnedAbout) {
  if (const std::string why = skipped_when_sanitized("crane_payload", false); !why.empty()) GTEST_SKIP() << why;
  TempDir dir("subset_truncation");
  std::string text = read_text(fs::path(TREEDYN_TEST_SUPPORT_DIR) / "crane_truncated_mass.toml");
  const std::size_t at = text.find("samples = 1000 ");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 15, "samples = 200 ");
  const fs::path job = dir.path() / "crane.toml";
  write_text(job, text);
  const auto r = run_ensemble(2, job, dir.path() / "crane.h5", dir.path() / "capture");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  H5File f(dir.path() / "crane.h5");
  const std::string g = "/rare_event/peak_tension/failure_region/";
  const std::vector<std::string> inputs = read_string_attribute(f.id(), g + "near_bound", "columns");
  ASSERT_EQ(inputs.back(), "body.container.mass");
  const std::vector<double> near = read_doubles(f.id(), g + "near_bound"), bound = read_doubles(f.id(), g + "bound");
  std::printf("%.0f %% of the runs beyond the limit have the mass within 1 %% of its range of 2500 kg\n",
              100.0 * near.back());
  EXPECT_GE(near.back(), 0.5) << "the summary's warning needs half";
  EXPECT_EQ(bound.back(), 2500.0);
  const fs::path report = dir.path() / "report";
  ASSERT_EQ(run_command(TREEDYN_BINARY, {"report", (dir.path() / "crane.h5").string(), "-o", report.string()},
                        dir.path() / "capture_report")
                .exit_code,
            0);
  const std::string summary = read_text(report / "summary.txt");
  EXPECT_NE(summary.find("of them have body.container.mass within 1 % of its range of its bound 2500 kg: P depends on "
                         "where that distribution is cut off"),
            std::string::npos)
      << summary;
}

}  // namespace

namespace {

// Every distribution goes through standard normal space: a subset
// simulation's level 0 is, bit for bit, the Monte-Carlo design of the same
// seed (orientation components, uniform, truncated normal and lognormal
// inputs here), and every later run's inputs stay in their distributions'
// supports.
TEST(SubsetInputs, LevelZeroIsTheMonteCarloDesignAndLaterRunsStayInTheSupports) {
  TempDir dir("subset_inputs");
  std::string text = spin_exceedance_job(200, false, "subset_simulation");
  text += "\n[ensemble.subset]\nresponse = \"spin0\"\nmax_levels = 2\n";
  const std::string lognormal =
      "\n[[ensemble.perturbation]]\ntarget = \"gravity.z\"\ndistribution = \"lognormal\"\n"
      "mu = 0.0\nsigma = 0.05\nmode = \"scale\"\n";
  text += lognormal;
  const fs::path job = dir.path() / "subset.toml";
  write_text(job, text);
  ASSERT_EQ(run_ensemble(2, job, dir.path() / "subset.h5", dir.path() / "capture_s").exit_code, 0);
  std::string mc = spin_exceedance_job(200, false, "monte_carlo") + lognormal;
  const fs::path mc_job = dir.path() / "mc.toml";
  write_text(mc_job, mc);
  ASSERT_EQ(run_ensemble(0, mc_job, dir.path() / "mc.h5", dir.path() / "capture_m").exit_code, 0);
  H5File s(dir.path() / "subset.h5"), m(dir.path() / "mc.h5");
  const DoubleArray subset = read_double_array(s.id(), "/samples/inputs"),
                    crude = read_double_array(m.id(), "/samples/inputs");
  ASSERT_EQ(subset.cols(), 6u);  // orientation x, y, z; spin; pivot; gravity
  ASSERT_GT(subset.rows(), 200u) << "the case never left level 0";
  for (std::size_t k = 0; k < 200; ++k)
    for (std::size_t d = 0; d < subset.cols(); ++d) ASSERT_EQ(subset(k, d), crude(k, d)) << k << ", " << d;
  for (std::size_t k = 200; k < subset.rows(); ++k) {
    EXPECT_GE(subset(k, 3), 1.8) << k;  // uniform [1.8, 2.2]
    EXPECT_LE(subset(k, 3), 2.2) << k;
    EXPECT_GE(subset(k, 4), 0.49) << k;  // truncated normal [0.49, 0.51]
    EXPECT_LE(subset(k, 4), 0.51) << k;
    EXPECT_GT(subset(k, 5), 0.0) << k;  // lognormal
    for (std::size_t d = 0; d < 3; ++d) EXPECT_TRUE(std::isfinite(subset(k, d))) << k;
  }
}

}  // namespace
