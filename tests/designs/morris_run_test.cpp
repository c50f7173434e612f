// Morris screening through whole runs of treedyn-ensemble: the spherical
// pendulum over 0.05 s with the spin at t = 0 as the response, which is the
// sampled input angular_velocity.z itself (uniform on [1.8, 2.2] rad/s). So
// its elementary effect is (2.2 - 1.8) rad/s per unit of u in every
// trajectory (mu = mu* = 0.4, sigma = 0, up to rounding) and the other
// factors' effects are 0; the ranking puts the spin first, told apart.
// The same bits on 1 and 3 ranks, in a merge of two parts, and in one run
// redone alone (--sample K).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "support/command.hpp"
#include "support/ensemble_run.hpp"
#include "support/hdf5_reader.hpp"

namespace {

using namespace treedyn::testing;
namespace fs = std::filesystem;

// 12 trajectories of 3 factors (the orientation's three inputs are one, a
// multi-input perturbation), 48 runs, radial steps.
std::string spin_screening_job() {
  std::string text = spin_exceedance_job(64, false, "morris");
  const std::string samples = "samples = 64\n";
  text.erase(text.find(samples), samples.size());
  return text + "\n[ensemble.morris]\ntrajectories = 12\n";
}

const std::vector<std::string> kCompared = {"/samples/inputs",
                                            "/sensitivity/spin0/morris_mu_star",
                                            "/sensitivity/spin0/morris_mu",
                                            "/sensitivity/spin0/morris_sigma",
                                            "/sensitivity/spin0/morris_mu_star_ci",
                                            "/sensitivity/spin0/morris_sigma_ci",
                                            "/responses/spin0/mean"};

std::vector<std::vector<double>> read_all(const fs::path& file) {
  H5File f(file);
  std::vector<std::vector<double>> out;
  for (const std::string& path : kCompared) out.push_back(read_doubles(f.id(), path));
  return out;
}

class MorrisRun : public ::testing::Test {
 protected:
  MorrisRun() : dir_("morris_run"), job_(dir_.path() / "spin.toml") { write_text(job_, spin_screening_job()); }
  fs::path out(const std::string& name) const { return dir_.path() / name; }
  TempDir dir_;
  fs::path job_;
};

// Either kind of step: a radial one divides a change of 0.4 x (b - a) by
// b - a (b - a may be as small as about 1e-4 here: rounding then reaches
// 1e-11, hence 1e-9); a trajectory's by 1/2.
class MorrisSpin : public MorrisRun, public ::testing::WithParamInterface<const char*> {};

TEST_P(MorrisSpin, EffectIsItsRangeOthersZeroOnAnyRanks) {
  std::string text = spin_screening_job();
  text.replace(text.find("trajectories = 12"), 17, std::string("trajectories = 12\nsteps = \"") + GetParam() + "\"");
  write_text(job_, text);
  const CommandResult one =
      run_command(TREEDYN_ENSEMBLE_BINARY, {job_.string(), "-o", out("one.h5").string()}, dir_.path() / "capture");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  EXPECT_NE(one.out.find("drivers (groups, Morris mu* [95 %], rad/s per unit of u, from 12 trajectories): "
                         "body.rod.angular_velocity.z 0.4"),
            std::string::npos)
      << one.out;
  H5File f(out("one.h5"));
  const std::vector<double> mu = read_doubles(f.id(), "/sensitivity/spin0/morris_mu");
  const std::vector<double> mu_star = read_doubles(f.id(), "/sensitivity/spin0/morris_mu_star");
  const std::vector<double> sigma = read_doubles(f.id(), "/sensitivity/spin0/morris_sigma");
  ASSERT_EQ(mu.size(), 3u);  // orientation, angular_velocity.z, joint_on_child.z
  EXPECT_NEAR(mu[1], 0.4, 1e-9);
  EXPECT_NEAR(mu_star[1], 0.4, 1e-9);
  EXPECT_NEAR(sigma[1], 0.0, 1e-9);
  for (std::size_t g : {0u, 2u}) EXPECT_NEAR(mu_star[g], 0.0, 1e-12) << g;
  EXPECT_EQ(read_integers(f.id(), "/sensitivity/spin0/morris_ranking/order").at(0), 1);
  EXPECT_EQ(read_integers(f.id(), "/sensitivity/spin0/morris_ranking/told_apart").at(0), 1);
  EXPECT_EQ(read_doubles(f.id(), "/sensitivity/spin0/morris_effects"), (std::vector<double>{12, 12, 12}));

  const CommandResult three = run_ensemble(3, job_, out("three.h5"), dir_.path() / "capture");
  ASSERT_EQ(three.exit_code, 0) << three.err;
  EXPECT_EQ(read_all(out("one.h5")), read_all(out("three.h5")));
}

INSTANTIATE_TEST_SUITE_P(Steps, MorrisSpin, ::testing::Values("radial", "trajectories"));

// Two parts over runs [0, 20) and [20, 48), merged: the same bits as one
// run; run 29 alone: the inputs of row 29.
TEST_F(MorrisRun, MergedPartsAndOneRunAloneAreTheSame) {
  const fs::path capture = dir_.path() / "capture";
  ASSERT_EQ(run_ensemble(0, job_, out("whole.h5"), capture).exit_code, 0);
  for (const char* range : {"0:20", "20:48"}) {
    const CommandResult part = run_command(
        TREEDYN_ENSEMBLE_BINARY,
        {job_.string(), "-o", out(std::string("part") + range[0]).string(), "--samples", range, "-q"}, capture);
    ASSERT_EQ(part.exit_code, 0) << part.err;
  }
  const CommandResult merge =
      run_command(TREEDYN_ENSEMBLE_BINARY,
                  {"merge", "-o", out("merged.h5").string(), out("part0").string(), out("part2").string()}, capture);
  ASSERT_EQ(merge.exit_code, 0) << merge.err;
  EXPECT_EQ(read_all(out("whole.h5")), read_all(out("merged.h5")));

  const CommandResult alone = run_command(
      TREEDYN_ENSEMBLE_BINARY, {job_.string(), "--sample", "29", "-o", out("run29.h5").string(), "-q"}, capture);
  ASSERT_EQ(alone.exit_code, 0) << alone.err;
  H5File whole(out("whole.h5")), run(out("run29.h5"));
  const std::vector<double> inputs = read_doubles(whole.id(), "/samples/inputs");
  const std::vector<double> mine = read_doubles(run.id(), "/sample/inputs");
  ASSERT_EQ(mine.size(), 5u);
  EXPECT_EQ(mine, std::vector<double>(inputs.begin() + 29 * 5, inputs.begin() + 30 * 5));
}

// Each wrong [ensemble.morris] or what Morris cannot do: exit 2, the field
// and the reason, nothing written.
TEST(MorrisJob, RefusedWithTheFieldAndTheReason) {
  const std::string job = spin_screening_job();
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string text = job;
    text.replace(text.find(from), from.size(), to);
    return text;
  };
  expect_job_refused(replaced("[ensemble]\n", "[ensemble]\nsamples = 10\n"),
                     {"samples: design = \"morris\" runs r trajectories", "trajectories = r"});
  expect_job_refused(replaced("\n[ensemble.morris]\ntrajectories = 12\n", ""),
                     {"design: morris needs an [ensemble.morris] table"});
  expect_job_refused(replaced("trajectories = 12", "trajectories = 1"), {"trajectories: must be at least 2"});
  expect_job_refused(replaced("trajectories = 12", "trajectories = 12\nsteps = \"trajectories\"\nlevels = 3"),
                     {"levels: must be an even integer from 2 to 1024"});
  expect_job_refused(replaced("trajectories = 12", "trajectories = 12\nlevels = 4"),
                     {"levels: only for steps = \"trajectories\""});
  expect_job_refused(replaced("trajectories = 12", "trajectories = 12\nsteps = \"grid\""),
                     {"steps: \"grid\" is not allowed; use \"radial\""});
  expect_job_refused(replaced("trajectories = 12", "trajectories = 12\nlevel = 4"), {"level"});
  expect_job_refused(replaced("design = \"morris\"", "design = \"sobol\"\nsamples = 10"),
                     {"[ensemble.morris] is only for design = \"morris\""});
  expect_job_refused(job +
                         "\n[[ensemble.correlation]]\ninputs = [\"body.rod.angular_velocity.z\", "
                         "\"body.rod.joint_on_child.z\"]\nspearman = 0.5\n",
                     {"Morris' elementary effects move one input (or group) at a time"});
  expect_job_refused(job + "\n[ensemble.stop]\nresponse = \"spin0\"\nmean_sem = 0.1\nevery = 4\n",
                     {"morris screens with all its trajectories"});
}

}  // namespace
