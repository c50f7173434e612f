// The treedyn-ensemble command line itself (one rank, no mpirun): --check,
// --version, --help, and a missing --output.
#include <gtest/gtest.h>

#include <filesystem>

#include "support/command.hpp"

namespace {

using namespace treedyn::testing;
namespace fs = std::filesystem;

CommandResult ensemble(const std::vector<std::string>& args, const TempDir& dir) {
  return run_command(TREEDYN_ENSEMBLE_BINARY, args, dir.path());
}

// --check validates the job and its [ensemble], prints both, writes nothing.
TEST(EnsembleCommand, CheckPrintsTheModelAndTheEnsembleAndRunsNothing) {
  TempDir dir("ensemble_command_test");
  const std::string job = std::string(TREEDYN_JOBS_DIR) + "/spherical_pendulum.toml";
  const CommandResult r = ensemble({"--check", job}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("tree (1 body)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("ensemble: 64 samples, seed 2026, design latin_hypercube, 3 perturbations "
                       "(5 sampled inputs)"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("body.rod.orientation: normal(mean=0, std=2)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(job + ": OK"), std::string::npos) << r.out;
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, 0u) << "--check must not write anything";
}

TEST(EnsembleCommand, CheckRefusesABadEnsembleWithTheFieldAndExit2) {
  TempDir dir("ensemble_command_test");
  const fs::path job = dir.path() / "job.toml";
  const std::string text = read_text(std::string(TREEDYN_JOBS_DIR) + "/spherical_pendulum.toml") +
                           "\n[[ensemble.perturbation]]\ntarget = \"body.rod.mass\"\n"
                           "distribution = \"uniform\"\nlower = 1.0\nupper = 0.5\n";
  write_text(job, text);
  fs::create_directory(dir.path() / "capture");
  const CommandResult r = run_command(TREEDYN_ENSEMBLE_BINARY, {"--check", job.string()},
                                      dir.path() / "capture");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("ensemble.perturbation[4].upper: must be greater than 'lower'"),
            std::string::npos)
      << r.err;
}

TEST(EnsembleCommand, RunWithoutOutputIsBadInput) {
  TempDir dir("ensemble_command_test");
  const CommandResult r =
      ensemble({std::string(TREEDYN_JOBS_DIR) + "/spherical_pendulum.toml"}, dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--output is required"), std::string::npos) << r.err;
}

TEST(EnsembleCommand, VersionAndHelp) {
  TempDir dir("ensemble_command_test");
  const CommandResult version = ensemble({"--version"}, dir);
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_EQ(version.out, std::string("treedyn-ensemble ") + TREEDYN_VERSION + "\n");
  const CommandResult help = ensemble({"--help"}, dir);
  EXPECT_EQ(help.exit_code, 0);
  for (const char* word : {"JOB", "--output", "--check", "--quiet", "--progress-interval", "Exit codes"})
    EXPECT_NE(help.out.find(word), std::string::npos) << word;
}

}  // namespace
