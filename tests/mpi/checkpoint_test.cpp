// Checkpoints, signals and resume of treedyn-ensemble, end to end under
// mpirun. An ensemble is killed with SIGKILL at several points (mpirun, or one
// rank alone), resumed on another number of ranks, and /stats and /samples
// must be bitwise those of an uninterrupted run. SIGTERM and SIGINT give exit
// 5, the message and a checkpoint, and leave no temporary file. A checkpoint
// of another job is refused; stale temporary files of dead processes are
// removed with a note.
//
// The job is the shipped Kapitza pendulum (Sobol design, two inputs, two
// responses), cut to 64 samples in blocks of 4 with 8 pilot samples, and a
// checkpoint every 0.2 s so that kills land between checkpoints.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "support/command.hpp"
#include "support/ensemble_run.hpp"
#include "support/hdf5_reader.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using namespace treedyn::testing;
using namespace std::chrono_literals;

std::string kapitza_job() {
  std::string text = read_text(fs::path(TREEDYN_JOBS_DIR) / "kapitza.toml");
  const std::string from = "samples = 128";
  const std::size_t at = text.find(from);
  if (at == std::string::npos) throw std::runtime_error("kapitza.toml changed: no 'samples = 128'");
  return text.replace(at, from.size(), "samples = 64\nblock_size = 4\npilot_samples = 8");
}

// An ensemble started in the background: `mpirun ... treedyn-ensemble` (or
// the binary alone when ranks == 0) through /bin/sh's exec, so the PID is
// mpirun's (or the binary's).
class Background {
 public:
  Background(int ranks, const fs::path& job, const fs::path& out, const std::vector<std::string>& extra,
             const fs::path& capture) {
    fs::create_directories(capture);
    err_ = capture / "stderr.txt";
    std::string line = "exec";
    if (ranks > 0) line += " " + quote(TREEDYN_MPIEXEC) + " --oversubscribe -np " + std::to_string(ranks);
    line += " " + quote(TREEDYN_ENSEMBLE_BINARY) + " " + quote(job.string()) + " -o " + quote(out.string()) + " -q";
    for (const auto& e : extra) line += " " + quote(e);
    line += " </dev/null >" + quote((capture / "stdout.txt").string()) + " 2>" + quote(err_.string());
    const char* argv[] = {"/bin/sh", "-c", line.c_str(), nullptr};
    if (posix_spawn(&pid_, "/bin/sh", nullptr, nullptr, const_cast<char**>(argv), environ) != 0)
      throw std::runtime_error("cannot start " + line);
  }
  ~Background() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      wait();
    }
  }
  pid_t pid() const { return pid_; }
  // The PIDs of mpirun's children: the ranks.
  std::vector<pid_t> ranks() const {
    std::vector<pid_t> out;
    for (const auto& entry : fs::directory_iterator("/proc")) {
      const std::string name = entry.path().filename().string();
      if (name.find_first_not_of("0123456789") != std::string::npos) continue;
      std::ifstream stat(entry.path() / "stat");
      std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
      const std::size_t close = text.rfind(')');
      if (close == std::string::npos) continue;
      std::istringstream rest(text.substr(close + 2));
      char state = 0;
      pid_t parent = 0;
      rest >> state >> parent;
      if (parent == pid_) out.push_back(static_cast<pid_t>(std::stol(name)));
    }
    return out;
  }
  int wait() {
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }
  std::string err() const { return read_text(err_); }

 private:
  pid_t pid_ = -1;
  fs::path err_;
};

// True once `pred` holds, polling every 20 ms for at most `limit`.
template <class Pred>
bool wait_for(Pred pred, std::chrono::milliseconds limit = 60s) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) return true;
    std::this_thread::sleep_for(20ms);
  }
  return false;
}

// Checkpoint parts of generation `generation` that already hold records.
int parts_with_records(const fs::path& dir, int generation = 0) {
  int n = 0;
  std::error_code ec;
  const std::string prefix = "part-" + std::to_string(generation) + "-";
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ".records" && e.path().filename().string().rfind(prefix, 0) == 0 &&
        e.file_size(ec) > 0)
      ++n;
  return n;
}

// No process of ours mentions `out` any more (orphaned ranks of a killed
// mpirun finish dying).
bool no_process_writes(const fs::path& out) {
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream cmd(entry.path() / "cmdline");
    std::string text((std::istreambuf_iterator<char>(cmd)), std::istreambuf_iterator<char>());
    if (text.find(out.string()) != std::string::npos) return false;
  }
  return true;
}

std::vector<std::string> listing(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

class Checkpoint : public ::testing::Test {
 protected:
  // One uninterrupted reference run for the whole suite.
  static void SetUpTestSuite() {
    shared_ = new TempDir("checkpoint_reference");
    const fs::path job = shared_->path() / "kapitza.toml";
    write_text(job, kapitza_job());
    const auto r = run_ensemble(2, job, shared_->path() / "ensemble.h5", shared_->path() / "capture",
                                {"--checkpoint-every", "0"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() {
    delete shared_;
    shared_ = nullptr;
  }
  void SetUp() override {
    ASSERT_NE(shared_, nullptr);
    job_ = dir_.path() / "kapitza.toml";
    write_text(job_, kapitza_job());
    reference_ = shared_->path() / "ensemble.h5";
    ASSERT_TRUE(fs::exists(reference_));
  }

  // The resumed run's output against the uninterrupted one.
  void expect_like_reference(const fs::path& out, const std::string& what) {
    H5File a(reference_), b(out);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(read_integer_attribute(b.id(), "samples_ok") + read_integer_attribute(b.id(), "samples_failed"), 64);
    expect_identical_datasets(a.id(), "uninterrupted", b.id(), what, {"/stats", "/samples", "/responses", "/sensitivity"});
  }

  fs::path fresh_output(const std::string& name) {
    fs::create_directory(dir_.path() / name);
    return dir_.path() / name / "ensemble.h5";
  }

  static TempDir* shared_;
  TempDir dir_{"checkpoint_test"};
  fs::path job_, reference_;
};

TempDir* Checkpoint::shared_ = nullptr;

const std::vector<std::string> kEvery = {"--checkpoint-every", "0.2"};

TEST_F(Checkpoint, KillNineOfMpirunOrOfOneRankThenResumeOnOtherRankCountsIsBitwiseIdentical) {
  struct Case {
    const char* what;
    int ranks, resume_ranks;
    bool one_rank;    // SIGKILL one rank instead of mpirun
    int parts;        // kill once this many parts hold records (0: right after common.state)
    std::chrono::milliseconds extra;
  };
  const Case cases[] = {
      {"mpirun killed right after the pilot, resumed on 3 ranks", 2, 3, false, 0, 0ms},
      {"mpirun killed mid-sweep, resumed alone (1 rank)", 2, 1, false, 2, 300ms},
      {"one rank killed mid-sweep, resumed on 2 ranks", 3, 2, true, 1, 200ms},
  };
  int index = 0;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    const fs::path out = fresh_output("kill" + std::to_string(index++));
    const fs::path ckpt = out.string() + ".checkpoint";
    {
      Background run(c.ranks, job_, out, kEvery, dir_.path() / "capture_bg");
      const bool reached = wait_for([&] {
        return c.parts == 0 ? fs::exists(ckpt / "common.state") : parts_with_records(ckpt) >= c.parts;
      });
      ASSERT_TRUE(reached) << "the run never got there: " << run.err();
      std::this_thread::sleep_for(c.extra);
      if (c.one_rank) {
        const auto ranks = run.ranks();
        ASSERT_FALSE(ranks.empty());
        ::kill(ranks.back(), SIGKILL);
      } else {
        ::kill(run.pid(), SIGKILL);
      }
      const int code = run.wait();
      std::printf("[%s] killed run: exit %d\n", c.what, code);
      ASSERT_NE(code, 0) << "the run finished before the kill: the case tests nothing";
    }
    ASSERT_TRUE(wait_for([&] { return no_process_writes(out); })) << "processes of the killed run live on";
    EXPECT_FALSE(fs::exists(out)) << "a killed run must not leave the output";
    const auto r = run_ensemble(c.resume_ranks, job_, out, dir_.path() / "capture", {"--resume", "--checkpoint-every", "0.2"});
    std::printf("[%s] resume: exit %d, %s", c.what, r.exit_code, r.err.c_str());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("resuming: "), std::string::npos) << r.err;
    // Killed once parts held records, a resume must restore some; killed right
    // after the pilot (common.state only), it may legitimately restore none.
    if (c.parts > 0) {
      EXPECT_EQ(r.err.find("resuming: 0 of"), std::string::npos) << "nothing was restored: " << r.err;
    }
    expect_like_reference(out, c.what);
    // Done: the checkpoint and every temporary are gone.
    EXPECT_EQ(listing(out.parent_path()), std::vector<std::string>{"ensemble.h5"});
  }
}

// Two generations: a resumed run is killed too, and resumed again.
TEST_F(Checkpoint, AResumedRunKilledAgainResumesAgain) {
  const fs::path out = fresh_output("twice");
  const fs::path ckpt = out.string() + ".checkpoint";
  for (int round = 0; round < 2; ++round) {
    std::vector<std::string> extra = kEvery;
    if (round == 1) extra.push_back("--resume");
    Background run(2, job_, out, extra, dir_.path() / "capture_bg");
    ASSERT_TRUE(wait_for([&] { return parts_with_records(ckpt, round) >= (round == 0 ? 2 : 1); })) << run.err();
    std::this_thread::sleep_for(150ms);
    ::kill(run.pid(), SIGKILL);
    ASSERT_NE(run.wait(), 0);
    ASSERT_TRUE(wait_for([&] { return no_process_writes(out); }));
  }
  EXPECT_TRUE(fs::exists(ckpt / "base-1.state")) << "the first resume consolidated nothing";
  const auto r = run_ensemble(3, job_, out, dir_.path() / "capture", {"--resume"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_like_reference(out, "resumed twice");
}

TEST_F(Checkpoint, SigtermAndSigintGiveExitFiveAMessageAndACheckpointAndNoTemporary) {
  struct Case {
    const char* what;
    int ranks;  // 0: the binary alone
    int signal_number;
  };
  const Case cases[] = {{"SIGTERM to every rank (as Slurm does)", 2, SIGTERM},
                        {"SIGINT to the binary alone (Ctrl-C)", 0, SIGINT},
                        {"SIGUSR1 to mpirun (forwarded to the ranks)", 2, SIGUSR1}};
  int index = 0;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    const fs::path out = fresh_output("signal" + std::to_string(index++));
    const fs::path ckpt = out.string() + ".checkpoint";
    Background run(c.ranks, job_, out, kEvery, dir_.path() / "capture_bg");
    ASSERT_TRUE(wait_for([&] { return parts_with_records(ckpt) >= 1; })) << run.err();
    if (c.ranks == 0 || c.signal_number == SIGUSR1) {
      ::kill(run.pid(), c.signal_number);
    } else {
      for (pid_t rank : run.ranks()) ::kill(rank, c.signal_number);
    }
    const int code = run.wait();
    const std::string err = run.err();
    std::printf("[%s] exit %d: %s\n", c.what, code, err.c_str());
    EXPECT_EQ(code, 5) << err;
    EXPECT_NE(err.find("interrupted by "), std::string::npos) << err;
    EXPECT_NE(err.find(" of 64 samples; resume with --resume"), std::string::npos) << err;
    // Nothing half-written: only the checkpoint directory.
    EXPECT_EQ(listing(out.parent_path()), std::vector<std::string>{"ensemble.h5.checkpoint"});
    for (const auto& f : listing(ckpt)) EXPECT_EQ(f.find(".tmp-"), std::string::npos) << f;
    const auto r = run_ensemble(c.ranks == 0 ? 0 : 3, job_, out, dir_.path() / "capture", {"--resume"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    expect_like_reference(out, std::string("resumed after ") + c.what);
  }
}

TEST_F(Checkpoint, ACheckpointOfAnotherJobIsRefusedAndAFreshRunDoesNotOverwriteOne) {
  const fs::path out = fresh_output("other");
  const fs::path ckpt = out.string() + ".checkpoint";
  {
    Background run(2, job_, out, kEvery, dir_.path() / "capture_bg");
    ASSERT_TRUE(wait_for([&] { return parts_with_records(ckpt) >= 1; })) << run.err();
    ::kill(run.pid(), SIGKILL);
    run.wait();
  }
  ASSERT_TRUE(wait_for([&] { return no_process_writes(out); }));
  // Another job (one changed number): exit 2, the checkpoint kept.
  const fs::path other = dir_.path() / "other.toml";
  std::string text = read_text(job_);
  text.replace(text.find("seed = 5"), 8, "seed = 6");
  write_text(other, text);
  auto r = run_ensemble(2, other, out, dir_.path() / "capture", {"--resume"});
  std::printf("[another job] exit %d: %s", r.exit_code, r.err.c_str());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("belongs to another job file"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(ckpt / "common.state"));
  // The same job without --resume: refused, nothing lost.
  r = run_ensemble(2, job_, out, dir_.path() / "capture");
  std::printf("[fresh run over a checkpoint] exit %d: %s", r.exit_code, r.err.c_str());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--resume"), std::string::npos) << r.err;
  // And it still resumes.
  r = run_ensemble(1, job_, out, dir_.path() / "capture", {"--resume"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_like_reference(out, "resumed after the refusals");
}

TEST_F(Checkpoint, StaleTemporaryFilesOfDeadProcessesAreRemovedWithANote) {
  const fs::path out = fresh_output("stale");
  // A PID that is certainly not running: a child that has exited.
  const pid_t dead = fork();
  if (dead == 0) _exit(0);
  waitpid(dead, nullptr, 0);
  const fs::path stale = out.string() + ".tmp-" + std::to_string(dead);
  write_text(stale, "half-written");
  const fs::path alive = out.string() + ".tmp-" + std::to_string(getpid());  // this test: alive
  write_text(alive, "someone else's, still running");
  const auto r = run_ensemble(2, job_, out, dir_.path() / "capture", {"--checkpoint-every", "0"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("note: removed " + stale.string()), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(alive)) << "the temporary of a live process must be kept";
  fs::remove(alive);
}

}  // namespace
