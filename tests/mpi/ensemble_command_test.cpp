// The treedyn-ensemble command line itself (one rank, no mpirun): --check,
// --version, --help, and a missing --output.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "support/command.hpp"
#include "support/ensemble_run.hpp"
#include "support/hdf5_reader.hpp"

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
  EXPECT_NE(r.out.find(" ns a byte of page-cache CPU measured now in . (a lower bound"), std::string::npos) << r.out;
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, 0u) << "--check must not write anything";
}

// With -o, --check measures writing in the output's directory (and leaves
// it empty); a directory it cannot write to is said, not an error: --check
// judges the job, and a run would refuse the output itself (exit 4).
TEST(EnsembleCommand, CheckMeasuresWritingWhereTheOutputGoes) {
  TempDir dir("ensemble_command_test");
  const std::string job = std::string(TREEDYN_JOBS_DIR) + "/spherical_pendulum.toml";
  fs::create_directory(dir.path() / "out");
  const std::string output = (dir.path() / "out" / "result.h5").string();
  CommandResult r = ensemble({"--check", job, "-o", output}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find(" ns a byte of page-cache CPU measured now in " + (dir.path() / "out").string() + " ("),
            std::string::npos)
      << r.out;
  EXPECT_TRUE(fs::is_empty(dir.path() / "out"));
  const fs::path missing = dir.path() / "missing";
  r = ensemble({"--check", job, "-o", (missing / "result.h5").string()}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("not measured here: " + missing.string() +
                       ": cannot measure what writing costs here: cannot create a file (No such file or directory)"),
            std::string::npos)
      << r.out;
  EXPECT_FALSE(fs::exists(missing));
}

// A run says its capacity at the pilot's end, with writing measured beside
// its output, and leaves only the output there.
TEST(EnsembleCommand, ARunMeasuresWritingBesideItsOutput) {
  TempDir dir("ensemble_command_test");
  fs::create_directory(dir.path() / "out");
  const std::string output = (dir.path() / "out" / "result.h5").string();
  const CommandResult r = ensemble(
      {std::string(TREEDYN_JOBS_DIR) + "/spherical_pendulum.toml", "-o", output, "--checkpoint-every", "0"}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("rank 0's capacity: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(" ns a byte of page-cache CPU measured now in " + (dir.path() / "out").string() + " ("),
            std::string::npos)
      << r.err;
  std::vector<std::string> left;
  for (const auto& entry : fs::directory_iterator(dir.path() / "out")) left.push_back(entry.path().filename());
  EXPECT_EQ(left, std::vector<std::string>{"result.h5"});
}

TEST(EnsembleCommand, CheckRefusesABadEnsembleWithTheFieldAndExit2) {
  TempDir dir("ensemble_command_test");
  const fs::path job = dir.path() / "job.toml";
  const std::string text = read_text(std::string(TREEDYN_JOBS_DIR) + "/spherical_pendulum.toml") +
                           "\n[[ensemble.perturbation]]\ntarget = \"body.rod.mass\"\n"
                           "distribution = \"uniform\"\nlower = 1.0\nupper = 0.5\n";
  write_text(job, text);
  fs::create_directory(dir.path() / "capture");
  const CommandResult r = run_command(TREEDYN_ENSEMBLE_BINARY, {"--check", job.string()}, dir.path() / "capture");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("ensemble.perturbation[4].upper: must be greater than 'lower'"), std::string::npos) << r.err;
}

// A distribution that draws values the model refuses (a normal on a mass):
// --check says how often, from the CDF (Phi(-0.5 / 0.3) = 4.78 %), and
// warns. `treedyn check` checks [ensemble] too: a misspelled key is refused.
TEST(EnsembleCommand, CheckWarnsOfSamplesTheModelWillRefuseAndTreedynCheckReadsTheEnsemble) {
  TempDir dir("ensemble_command_test");
  const fs::path job = dir.path() / "job.toml";
  const std::string base = read_text(std::string(TREEDYN_JOBS_DIR) + "/spherical_pendulum.toml");
  write_text(job, base +
                      "\n[[ensemble.perturbation]]\ntarget = \"body.rod.mass\"\ndistribution = \"normal\"\n"
                      "mean = 0.5\nstd = 0.3\n");
  fs::create_directory(dir.path() / "capture");
  CommandResult r = run_command(TREEDYN_ENSEMBLE_BINARY, {"--check", job.string()}, dir.path() / "capture");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("outside the model's range (body.rod.mass > 0 kg): 4.78 % of the samples"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("warning: 4.78 % of the samples will fail as invalid models"), std::string::npos) << r.out;
  // The pivot's truncated normal stays in range: no warning for it.
  EXPECT_EQ(r.out.find("warning", r.out.find("body.rod.joint_on_child.z")), r.out.find("warning: 4.78"));

  std::string misspelled = base;
  misspelled.replace(misspelled.find("seed = 2026"), 11, "seed = 2026\nstore_trajectory = 4");
  write_text(job, misspelled);
  r = run_command(TREEDYN_BINARY, {"check", job.string()}, dir.path() / "capture");
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(r.err.find("ensemble.store_trajectory: unknown key"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("did you mean 'store_trajectories'"), std::string::npos) << r.err;
  r = run_command(TREEDYN_BINARY, {"check", (std::string(TREEDYN_JOBS_DIR) + "/spherical_pendulum.toml")},
                  dir.path() / "capture");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("[ensemble]: checked too"), std::string::npos) << r.out;
}

TEST(EnsembleCommand, RunWithoutOutputIsBadInput) {
  TempDir dir("ensemble_command_test");
  const CommandResult r = ensemble({std::string(TREEDYN_JOBS_DIR) + "/spherical_pendulum.toml"}, dir);
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

// One sample's outputs into a directory that does not exist: exit 4, the
// path named, nothing written anywhere.
TEST(EnsembleCommand, SampleOutputsThatCannotBeWrittenAreIoErrors) {
  TempDir dir("ensemble_command_test");
  fs::create_directory(dir.path() / "capture");
  const std::string job = std::string(TREEDYN_JOBS_DIR) + "/kapitza.toml";
  for (const auto& [flag, name] : {std::pair{"--sample", "s.h5"}, std::pair{"--write-job", "s.toml"}}) {
    SCOPED_TRACE(flag);
    const fs::path out = dir.path() / "missing" / name;
    const CommandResult r =
        run_command(TREEDYN_ENSEMBLE_BINARY, {job, flag, "3", "-o", out.string(), "-q"}, dir.path() / "capture");
    EXPECT_EQ(r.exit_code, 4) << r.out << r.err;
    EXPECT_NE(r.err.find((dir.path() / "missing").string()), std::string::npos) << r.err;
    EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1) << "only capture/";
  }
  // --write-job into a directory it cannot write (read-only): no file, no temporary left.
  const fs::path locked = dir.path() / "locked";
  fs::create_directory(locked);
  fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
  const CommandResult r = run_command(
      TREEDYN_ENSEMBLE_BINARY, {job, "--write-job", "3", "-o", (locked / "s.toml").string()}, dir.path() / "capture");
  if (::geteuid() != 0) {  // root writes anyway
    EXPECT_EQ(r.exit_code, 4) << r.err;
    EXPECT_TRUE(fs::is_empty(locked));
  }
  fs::permissions(locked, fs::perms::owner_all);
}

// The ensemble itself (and a part of one) into a directory that does not
// exist: exit 4 before any work, as `treedyn run` does, and the directory is
// not created (a checkpoint directory once made its parent).
TEST(EnsembleCommand, AnEnsembleIntoAMissingDirectoryIsAnIoErrorAndCreatesNothing) {
  TempDir dir("ensemble_command_test");
  const std::string job = std::string(TREEDYN_JOBS_DIR) + "/kapitza.toml";
  for (int ranks : {0, 2})
    for (const std::vector<std::string>& extra : {std::vector<std::string>{}, {"--samples", "0:16"}}) {
      SCOPED_TRACE(describe(ranks) + (extra.empty() ? "" : ", a part"));
      const fs::path out = dir.path() / "nodir" / "x.h5";
      const CommandResult r = run_ensemble(ranks, job, out, dir.path() / "capture", extra);
      EXPECT_EQ(r.exit_code, 4) << r.err;
      EXPECT_NE(r.err.find("directory " + (dir.path() / "nodir").string() + " does not exist"), std::string::npos)
          << r.err;
      EXPECT_FALSE(fs::exists(dir.path() / "nodir"));
    }
}

// Slurm asked for 4 tasks, MPI sees one rank: refused before any work.
TEST(EnsembleCommand, SlurmTasksWithOneMpiRankAreRefused) {
  TempDir dir("ensemble_command_test");
  fs::create_directory(dir.path() / "capture");
  const fs::path out = dir.path() / "out.h5";
  const CommandResult r = run_command(
      TREEDYN_ENSEMBLE_BINARY, {std::string(TREEDYN_JOBS_DIR) + "/spherical_pendulum.toml", "-o", out.string(), "-q"},
      dir.path() / "capture", {"env", "SLURM_NTASKS=4"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("SLURM_NTASKS=4 but MPI sees 1 rank"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("srun --mpi=pmix"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1) << "only capture/";
  // One task is a normal serial run.
  const CommandResult one =
      run_command(TREEDYN_ENSEMBLE_BINARY, {"--check", std::string(TREEDYN_JOBS_DIR) + "/spherical_pendulum.toml"},
                  dir.path() / "capture", {"env", "SLURM_NTASKS=1"});
  EXPECT_EQ(one.exit_code, 0) << one.err;
}

// An srun task of 4 without PMI (`srun --mpi=none`): refused before MPI_Init
// (which would fail there with a bare "internal error"), in words by task 0,
// silently by the others; with PMI in the environment it is not refused.
TEST(EnsembleCommand, SrunTasksWithoutPmiAreRefusedBeforeMpiStarts) {
  TempDir dir("ensemble_command_test");
  fs::create_directory(dir.path() / "capture");
  const fs::path out = dir.path() / "out.h5";
  const std::vector<std::string> args = {std::string(TREEDYN_JOBS_DIR) + "/spherical_pendulum.toml", "-o", out.string(),
                                         "-q"};
  const CommandResult first = run_command(TREEDYN_ENSEMBLE_BINARY, args, dir.path() / "capture",
                                          {"env", "SLURM_PROCID=0", "SLURM_STEP_NUM_TASKS=4", "SLURM_NTASKS=4"});
  EXPECT_EQ(first.exit_code, 2) << first.err;
  EXPECT_NE(first.err.find("started by srun as one of 4 tasks without a process manager interface"), std::string::npos)
      << first.err;
  EXPECT_NE(first.err.find("srun --mpi=pmix"), std::string::npos) << first.err;
  const CommandResult other = run_command(TREEDYN_ENSEMBLE_BINARY, args, dir.path() / "capture",
                                          {"env", "SLURM_PROCID=3", "SLURM_STEP_NUM_TASKS=4", "SLURM_NTASKS=4"});
  EXPECT_EQ(other.exit_code, 2);
  EXPECT_EQ(other.err, "");
  EXPECT_FALSE(fs::exists(out));
  // PMIx present (srun --mpi=pmix sets it; here a singleton in fact): not this refusal but the one after MPI_Init.
  const CommandResult pmix =
      run_command(TREEDYN_ENSEMBLE_BINARY, args, dir.path() / "capture",
                  {"env", "SLURM_PROCID=0", "SLURM_STEP_NUM_TASKS=4", "SLURM_NTASKS=4", "PMIX_RANK=0"});
  EXPECT_EQ(pmix.err.find("without a process manager interface"), std::string::npos) << pmix.err;
  // The batch script of a 4-task job (SLURM_PROCID=0, SLURM_NTASKS=4, no step): --check runs there (the
  // array script reads the sample count so), and a run is refused after MPI_Init, not by this guard.
  const std::vector<std::string> batch = {"env", "SLURM_PROCID=0", "SLURM_NTASKS=4"};
  const CommandResult check =
      run_command(TREEDYN_ENSEMBLE_BINARY, {std::string(TREEDYN_JOBS_DIR) + "/spherical_pendulum.toml", "--check"},
                  dir.path() / "capture", batch);
  EXPECT_EQ(check.exit_code, 0) << check.err;
  const CommandResult run = run_command(TREEDYN_ENSEMBLE_BINARY, args, dir.path() / "capture", batch);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("SLURM_NTASKS=4 but MPI sees 1 rank"), std::string::npos) << run.err;
  // --check inside a 4-task step without PMI: no ranks needed, let through.
  const CommandResult step_check =
      run_command(TREEDYN_ENSEMBLE_BINARY, {std::string(TREEDYN_JOBS_DIR) + "/spherical_pendulum.toml", "--check"},
                  dir.path() / "capture", {"env", "SLURM_PROCID=0", "SLURM_STEP_NUM_TASKS=4", "SLURM_NTASKS=4"});
  EXPECT_EQ(step_check.exit_code, 0) << step_check.err;
}

// ---------------------------------------------------------------------------
// Bad [ensemble] answers input: FILE:LINE:COLUMN: FIELD, what was wrong and
// what is allowed, exit 2, nothing written.

// The Kapitza ensemble (it records orientation, angular_velocity,
// com_position, joint_angle, energy and base, and has two responses) with
// `extra` appended to the job and `ensemble_extra` put inside [ensemble].
void expect_refused(const std::string& extra, const std::vector<std::string>& words,
                    const std::string& ensemble_extra = "") {
  std::string text = read_text(std::string(TREEDYN_JOBS_DIR) + "/kapitza.toml");
  if (!ensemble_extra.empty()) {
    const std::size_t at = text.find("[ensemble]\n");
    text.insert(at + 11, ensemble_extra);
  }
  expect_job_refused(text + extra, words);
}

const std::string kResponse = "\n[[ensemble.response]]\nname = \"tip_low\"\n";  // the third

TEST(EnsembleBadAnswers, ResponseOnAQuantityThatIsNotRecorded) {
  expect_refused(kResponse + "quantity = \"joint_reaction\"\ncolumn = \"rod.z\"\nreduce = \"max\"\n",
                 {"ensemble.response[3].quantity", "\"joint_reaction\" is not recorded; use one of: ",
                  "(or add it to [output] quantities)", "joint_angle"});
}

TEST(EnsembleBadAnswers, UnknownColumnSuggestsTheNearest) {
  expect_refused(kResponse + "quantity = \"com_position\"\ncolumn = \"rod.zz\"\nreduce = \"min\"\n",
                 {"ensemble.response[3].column",
                  "\"rod.zz\" is not a column of com_position; its columns: rod.x rod.y rod.z; did you mean 'rod.z'?"});
}

TEST(EnsembleBadAnswers, LimitWithoutFailIf) {
  expect_refused(kResponse + "quantity = \"com_position\"\ncolumn = \"rod.z\"\nreduce = \"min\"\nlimit = -0.5\n",
                 {"ensemble.response[3].limit", "needs fail_if = \"above\" or \"below\""});
}

TEST(EnsembleBadAnswers, AtTimeOutsideTheOutputTimes) {
  expect_refused(kResponse + "quantity = \"com_position\"\ncolumn = \"rod.z\"\nreduce = \"at_time\"\ntime = 99.0\n",
                 {"ensemble.response[3].time", "99 s is outside the output times [0, "});
}

TEST(EnsembleBadAnswers, UnknownReductionAndDuplicateNames) {
  expect_refused(kResponse + "quantity = \"com_position\"\ncolumn = \"rod.z\"\nreduce = \"median\"\n",
                 {"ensemble.response[3].reduce", "\"median\" is not allowed", "first_time_below"});
  const std::string one = kResponse + "quantity = \"com_position\"\ncolumn = \"rod.z\"\nreduce = \"min\"\n";
  expect_refused(one + one, {"ensemble.response[4].name", "defined twice"});
  expect_refused("", {"ensemble.per_sample", "not a reduction", "argmax_time"}, "per_sample = [\"max\", \"mode\"]\n");
}

TEST(EnsembleBadAnswers, SaltelliWithoutPerturbations) {
  TempDir dir("ensemble_command_test");
  const fs::path job = dir.path() / "job.toml";
  std::string text = read_text(std::string(TREEDYN_JOBS_DIR) + "/double_pendulum.toml");
  text = text.substr(0, text.find("[ensemble]")) + "[ensemble]\nsamples = 8\ndesign = \"saltelli\"\n";
  write_text(job, text);
  fs::create_directory(dir.path() / "capture");
  const CommandResult r = run_command(TREEDYN_ENSEMBLE_BINARY, {"--check", job.string()}, dir.path() / "capture");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("ensemble.design: saltelli needs at least one [[ensemble.perturbation]]"), std::string::npos)
      << r.err;
}

TEST(EnsembleBadAnswers, SaltelliBeyondTheSampleIndexLimit) {
  // 5 inputs: 7 runs per base point; 2^26 runs at most.
  TempDir dir("ensemble_command_test");
  std::string text = read_text(std::string(TREEDYN_JOBS_DIR) + "/spherical_pendulum.toml");
  const std::size_t at = text.find("samples = 64");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 12, "samples = 700000000\ndesign = \"saltelli\"");
  const std::size_t design = text.find("design = \"latin_hypercube\"");
  if (design != std::string::npos) text.erase(design, 26);
  const fs::path job = dir.path() / "job.toml";
  write_text(job, text);
  fs::create_directory(dir.path() / "capture");
  const CommandResult r = run_command(TREEDYN_ENSEMBLE_BINARY, {"--check", job.string()}, dir.path() / "capture");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("ensemble.samples: saltelli makes samples x (D + 2) = 700000000 x 7 runs; at most "
                       "67108864 (2^26, so that the exact 128-bit sums cannot overflow): use at most 9586980"),
            std::string::npos)
      << r.err;
}

// The exact 128-bit sums hold 2^26 samples at the out-of-range bound: more
// is refused before any work.
TEST(EnsembleBadAnswers, MoreSamplesThanTheExactSumsHoldAreRefused) {
  TempDir dir("ensemble_command_test");
  std::string text = read_text(std::string(TREEDYN_JOBS_DIR) + "/spherical_pendulum.toml");
  const std::size_t at = text.find("samples = 64");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 12, "samples = 67108865");
  const fs::path job = dir.path() / "job.toml";
  write_text(job, text);
  fs::create_directory(dir.path() / "capture");
  const CommandResult r = run_command(TREEDYN_ENSEMBLE_BINARY, {"--check", job.string()}, dir.path() / "capture");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(":" + position_of(text, "67108865") + ": ensemble.samples: 67108865 samples: at most 67108864"),
            std::string::npos)
      << r.err;
}

// The statistics must fit in the node's memory before any work: exit 6, one
// message with what is needed and what is there, nothing written. The
// memory available is forced down with TREEDYN_MEMORY_AVAILABLE.
TEST(EnsembleBadAnswers, StatisticsLargerThanTheAvailableMemoryAreRefusedBeforeAnyWork) {
  TempDir dir("ensemble_command_test");
  const fs::path out = dir.path() / "out" / "ensemble.h5";
  fs::create_directories(out.parent_path());
  setenv("TREEDYN_MEMORY_AVAILABLE", "1000000", 1);  // 1 MB
  for (int ranks : {0, 2}) {
    const CommandResult r =
        run_ensemble(ranks, fs::path(TREEDYN_JOBS_DIR) / "kapitza.toml", out, dir.path() / "capture");
    std::printf("[memory, %s] exit %d: %s", describe(ranks).c_str(), r.exit_code, r.err.c_str());
    EXPECT_EQ(r.exit_code, 6) << r.err;
    EXPECT_NE(r.err.find("error: not enough memory on "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("GiB per rank"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::is_empty(out.parent_path())) << "nothing may be written";
  }
  unsetenv("TREEDYN_MEMORY_AVAILABLE");
}

// An allocation that fails although the memory check passed (a limit the
// check cannot see: ulimit -v here) ends with exit 6 and a message on every
// rank count, no MPI_ABORT banner, and nothing on disk (no temporary output,
// no empty checkpoint directory). The statistics (2501 times x 24 columns x
// 12,000 bins, 2.9 GB) do not fit in 2.5 GB of address space. AddressSanitizer
// reserves terabytes of address space, so the test cannot run under it.
TEST(EnsembleBadAnswers, AnAllocationThatFailsExitsSixAndLeavesNothing) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "ulimit -v cannot be combined with AddressSanitizer's shadow memory";
#endif
  TempDir dir("ensemble_command_test");
  std::string text = read_text(std::string(TREEDYN_JOBS_DIR) + "/kapitza.toml");
  text.replace(text.find("samples = 128"), 13, "samples = 16\nhistogram_bins = 12000");
  const fs::path job = dir.path() / "big.toml";
  write_text(job, text);
  const fs::path out = dir.path() / "out" / "ensemble.h5";
  fs::create_directories(out.parent_path());
  setenv("TREEDYN_MEMORY_AVAILABLE", "100000000000", 1);  // the check passes: the limit is ulimit's
  for (int ranks : {0, 2}) {
    std::vector<std::string> prefix = {"sh", "-c", "ulimit -v 2500000 && exec \"$@\"", "sh", "timeout", "120"};
    if (ranks > 0) prefix.insert(prefix.end(), {TREEDYN_MPIEXEC, "--oversubscribe", "-np", std::to_string(ranks)});
    const CommandResult r =
        run_command(TREEDYN_ENSEMBLE_BINARY, {job.string(), "-o", out.string(), "-q"}, dir.path() / "capture", prefix);
    std::printf("[allocation, %s] exit %d: %s", describe(ranks).c_str(), r.exit_code, r.err.c_str());
    EXPECT_EQ(r.exit_code, 6) << r.err;
    EXPECT_NE(r.err.find("error: out of memory"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("MPI_ABORT"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::is_empty(out.parent_path())) << "nothing may be left";
  }
  unsetenv("TREEDYN_MEMORY_AVAILABLE");
}

// A job file over 64 KiB (a 3000-point tabulated base, as docs/jobs.md allows)
// used to fail after the whole run ("creating attribute job_text failed"):
// the job text is a variable-length string now, of any size, in both files.
TEST(EnsembleLongJob, AJobFileOver64KiBIsStoredWholeByBothCommands) {
  TempDir dir("ensemble_command_test");
  std::string times = "times = [", positions = "positions = [";
  for (int k = 0; k < 3000; ++k) {
    const double t = 0.001 * k;
    times += (k ? ", " : "") + std::to_string(t);
    positions += std::string(k ? ", " : "") + "[" + std::to_string(0.01 * std::sin(20.0 * t)) + ", 0.0, 0.0]";
  }
  const std::string text =
      "[[body]]\nname = \"rod\"\nmass = 1.0\nprincipal_moments = [0.1, 0.1, 0.01]\nparent = \"base\"\n"
      "joint_on_child = [0.0, 0.0, 0.5]\n\n[base]\ntype = \"tabulated\"\n" +
      times + "]\n" + positions +
      "]\n\n[output]\nend_time = 0.5\nstep = 0.1\n\n[ensemble]\nsamples = 4\n"
      "[[ensemble.perturbation]]\ntarget = \"body.rod.mass\"\ndistribution = \"uniform\"\nlower = 0.9\nupper = 1.1\n";
  ASSERT_GT(text.size(), 65536u);
  const fs::path job = dir.path() / "long.toml";
  write_text(job, text);
  const fs::path ensemble = dir.path() / "ensemble.h5", trajectory = dir.path() / "run.h5";
  const CommandResult e = run_ensemble(2, job, ensemble, dir.path() / "capture");
  ASSERT_EQ(e.exit_code, 0) << e.err;
  const CommandResult r =
      run_command(TREEDYN_BINARY, {"run", job.string(), "-o", trajectory.string()}, dir.path() / "capture");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const fs::path& f : {ensemble, trajectory}) {
    H5File file(f);
    ASSERT_TRUE(file.ok());
    EXPECT_EQ(read_single_string_attribute(file.id(), "job_text"), text) << f;
  }
}

TEST(EnsembleBadAnswers, StoredTrajectoriesOverTheMemoryLimit) {
  // One trajectory is 2501 output times x 24 columns (469 KiB); a block of
  // 100000 would need 45 GiB.
  expect_refused("", {"ensemble.store_trajectories", "at most 1 GiB", "block_size = 1"},
                 "store_trajectories = 100\nblock_size = 100000\n");
  expect_refused("", {"ensemble.store_trajectories", "is more than the 128 samples"}, "store_trajectories = 129\n");
}
