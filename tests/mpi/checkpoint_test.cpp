// Checkpoints, signals and resume of treedyn-ensemble, end to end under
// mpirun. An ensemble is killed with SIGKILL at several points (mpirun, or one
// rank alone), resumed on another number of ranks, and /stats and /samples
// must be bitwise those of an uninterrupted run. SIGTERM and SIGINT give exit
// 5, the message and a checkpoint, and leave no temporary file. A checkpoint
// of another job is refused; stale temporary files of dead processes are
// removed with a note.
//
// The job is the shipped Kapitza pendulum (Sobol design, two inputs, two
// responses), cut to 64 samples of 1 s in blocks of 4 with 8 pilot samples. The
// tests act on a known state, never at a guessed moment: the run holds
// (--test-hold-after) after a given number of samples and says so in
// a file, and the test kills or signals it then; the number of samples a
// resume restores is known exactly.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
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

// The Kapitza example with 64 samples over 1 s of motion instead of 5.
std::string kapitza_job() {
  return edited_job_text("kapitza.toml", {{"samples = 128", "samples = 64\nblock_size = 4\npilot_samples = 8"},
                                          {"end_time = 5.0", "end_time = 1.0"}});
}

// An ensemble started in the background through /bin/sh's exec, so the PID
// is that of the first word (mpirun, `timeout`, `script`, or the binary
// alone when ranks == 0). `hold` is --test-hold-after (test_hooks.hpp):
// every rank holds after that many samples past the pilot and writes
// held-rankR into the checkpoint, so a test acts on a known state instead of
// a guessed moment. `wrapper` words go before mpirun; with `pty`, stdin is a
// pipe the test writes to (a terminal's keys, through `script`).
struct Launch {
  int ranks = 2;
  std::vector<std::string> extra;
  std::optional<int> hold;
  bool unsaved = false;  // --test-hold-unsaved: only a signal's save reaches the disk
  std::vector<std::string> wrapper;
  bool pty = false;
  std::vector<std::string> environment;  // NAME=VALUE words for the launch (io_faults)
};

Launch held_run(int ranks, std::vector<std::string> extra, int hold, bool unsaved = false) {
  Launch l;
  l.ranks = ranks;
  l.extra = std::move(extra);
  l.hold = hold;
  l.unsaved = unsaved;
  return l;
}

class Background {
 public:
  Background(const fs::path& job, const fs::path& out, const Launch& launch, const fs::path& capture) {
    fs::create_directories(capture);
    err_ = capture / "stderr.txt";
    out_ = capture / "stdout.txt";
    std::string command;
    if (launch.ranks > 0)
      command += quote(TREEDYN_MPIEXEC) + " --oversubscribe -np " + std::to_string(launch.ranks) + " ";
    command += quote(TREEDYN_ENSEMBLE_BINARY) + " " + quote(job.string()) + " -o " + quote(out.string()) + " -q";
    for (const auto& e : launch.extra) command += " " + quote(e);
    if (launch.hold) command += " --test-hold-after " + std::to_string(*launch.hold);
    if (launch.unsaved) command += " --test-hold-unsaved";
    std::string line = "exec env " + launcher_environment(launch.ranks > 0);
    for (const auto& e : launch.environment) line += " " + quote(e);
    for (const auto& w : launch.wrapper) line += " " + quote(w);
    line += launch.pty ? " script -qec " + quote(command) + " /dev/null" : " " + command;
    line += launch.pty ? "" : " </dev/null";
    line += " >" + quote(out_.string()) + " 2>" + quote(err_.string());
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    if (launch.pty) {
      int fds[2];
      if (pipe(fds) != 0) throw std::runtime_error("pipe");
      keys_ = fds[1];
      posix_spawn_file_actions_adddup2(&actions, fds[0], 0);
      posix_spawn_file_actions_addclose(&actions, fds[1]);
      read_end_ = fds[0];
    }
    const char* argv[] = {"/bin/sh", "-c", line.c_str(), nullptr};
    const int spawned = posix_spawn(&pid_, "/bin/sh", &actions, nullptr, const_cast<char**>(argv), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (read_end_ >= 0) ::close(read_end_);
    if (spawned != 0) throw std::runtime_error("cannot start " + line);
  }
  ~Background() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      wait();
    }
    if (keys_ >= 0) ::close(keys_);
  }
  pid_t pid() const { return pid_; }
  // Keys typed at the terminal (Launch::pty).
  void type(const std::string& keys) {
    ASSERT_EQ(::write(keys_, keys.data(), keys.size()), static_cast<ssize_t>(keys.size()));
  }
  int wait() {
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }
  std::string err() const { return read_text(err_) + read_text(out_); }

 private:
  pid_t pid_ = -1;
  int keys_ = -1, read_end_ = -1;
  fs::path err_, out_;
};

// What the held ranks wrote: each rank's PID and the samples it has kept.
struct Held {
  int rank = 0;
  pid_t pid = 0;
  long kept = 0;
};
// In rank order (a directory lists in no set order: the victim of a "kill
// one rank" case must be the last rank, never rank 0, whose records of the
// pilot samples are on disk already).
std::vector<Held> held_ranks(const fs::path& checkpoint) {
  std::vector<Held> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(checkpoint, ec)) {
    const std::string name = e.path().filename().string();
    // Not its temporary (held-rankR.tmp-PID, written then renamed): listed
    // before the rename, it made a held rank's files look touched later.
    if (name.rfind("held-rank", 0) != 0 || name.find('.') != std::string::npos) continue;
    std::istringstream in(read_text(e.path()));
    std::string pid_word, kept_word;
    Held h;
    h.rank = std::stoi(name.substr(std::string("held-rank").size()));
    in >> pid_word >> h.pid >> kept_word >> h.kept;
    if (in) out.push_back(h);
  }
  std::sort(out.begin(), out.end(), [](const Held& a, const Held& b) { return a.rank < b.rank; });
  return out;
}

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

// The command line of a /proc entry, or "" for a process that ended while
// it was read: its cmdline then fails with ESRCH, which libstdc++'s filebuf
// throws as std::ios_base::failure (seen on a loaded CI machine).
std::string command_line(const fs::path& process) {
  try {
    std::ifstream cmd(process / "cmdline");
    return {std::istreambuf_iterator<char>(cmd), std::istreambuf_iterator<char>()};
  } catch (const std::ios_base::failure&) {
    return {};
  }
}

// The processes whose command line mentions `out`: the run's mpirun and
// ranks (orphaned ranks of a killed mpirun finish dying).
std::vector<pid_t> processes_writing(const fs::path& out) {
  std::vector<pid_t> pids;
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    if (command_line(entry.path()).find(out.string()) != std::string::npos) pids.push_back(std::stoi(name));
  }
  return pids;
}
bool no_process_writes(const fs::path& out) { return processes_writing(out).empty(); }

// Waits until no process writes `out`. False when some still do after the
// wait: those are killed (SIGKILL), so that a failed test leaves no rank
// running into the next ones.
bool run_is_gone(const fs::path& out) {
  if (wait_for([&] { return no_process_writes(out); })) return true;
  for (pid_t pid : processes_writing(out)) ::kill(pid, SIGKILL);
  return false;
}

// `env` words that preload tests/support/io_faults.c into a run: every
// fsync logged into `fsync_log`, and a rename onto `fail_rename` (if given)
// failing with EIO. The preloaded library comes before AddressSanitizer's.
std::vector<std::string> io_faults(const fs::path& fsync_log, const fs::path& fail_rename = {}) {
  std::vector<std::string> words = {std::string("LD_PRELOAD=") + TREEDYN_IO_FAULTS_LIBRARY,
                                    "TREEDYN_TEST_FSYNC_LOG=" + fsync_log.string(),
                                    "ASAN_OPTIONS=detect_leaks=0:abort_on_error=1:verify_asan_link_order=0"};
  if (!fail_rename.empty()) words.push_back("TREEDYN_TEST_FAIL_RENAME_TO=" + fail_rename.string());
  return words;
}

// The lines of an fsync log (io_faults): what was flushed, in order.
std::vector<std::string> flushed_paths(const fs::path& fsync_log) {
  std::vector<std::string> paths;
  std::istringstream lines(fs::exists(fsync_log) ? read_text(fsync_log) : "");
  for (std::string line; std::getline(lines, line);) paths.push_back(line);
  return paths;
}

// Where in `paths` rank r's state (part-G-rankR.state, or its temporary
// .state.tmp-PID) was flushed last: a flushed save flushes its temporary
// before the rename, a stop's save is flushed in place. -1 when never.
long state_flushed_at(const std::vector<std::string>& paths, int rank) {
  long at = -1;
  for (std::size_t k = 0; k < paths.size(); ++k) {
    const std::string name = fs::path(paths[k]).filename().string();
    if (name.rfind("part-", 0) == 0 && name.find("-rank" + std::to_string(rank) + ".state") != std::string::npos)
      at = static_cast<long>(k);
  }
  return at;
}

// Every rank of a run of `ranks` (0: alone) flushed its state.
void expect_each_rank_flushed_its_state(const fs::path& fsync_log, int ranks) {
  const std::vector<std::string> paths = flushed_paths(fsync_log);
  for (int r = 0; r < std::max(ranks, 1); ++r)
    EXPECT_GE(state_flushed_at(paths, r), 0) << "rank " << r << "; flushed: " << ::testing::PrintToString(paths);
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
    const auto r =
        run_ensemble(2, job, shared_->path() / "ensemble.h5", shared_->path() / "capture", {"--checkpoint-every", "0"});
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
    expect_identical_datasets(a.id(), "uninterrupted", b.id(), what,
                              {"/stats", "/samples", "/responses", "/sensitivity", "/integration_check"});
  }

  void expect_clean_stop(const struct SignalCase& c, int index);

  fs::path fresh_output(const std::string& name) {
    fs::create_directory(dir_.path() / name);
    return dir_.path() / name / "ensemble.h5";
  }

  static TempDir* shared_;
  TempDir dir_{"checkpoint_test"};
  fs::path job_, reference_;
};

TempDir* Checkpoint::shared_ = nullptr;

// The major version of the Open MPI under test (0 when unknown).
int open_mpi_major() {
  static const int major = [] {
    TempDir dir("mpirun_version");
    const CommandResult r = run_command(TREEDYN_MPIEXEC, {"--version"}, dir.path());
    const std::size_t at = r.out.find("(Open MPI) ");
    return at == std::string::npos ? 0 : std::atoi(r.out.c_str() + at + 11);
  }();
  return major;
}

// Once Open MPI 5's mpirun (prterun) ends a job on SIGINT or SIGTERM, it no
// longer forwards what the ranks print: the ranks stop and save all the same
// (the restored count says so), but the hint line never reaches the
// terminal. Open MPI 4.1's mpirun prints it.
bool launcher_forwards_last_words() { return open_mpi_major() == 4; }

// When Open MPI 5's mpirun ends a job (it was signalled, or a rank died) it
// sends the ranks SIGCONT, SIGTERM 0.25 s later and SIGKILL 0.25 s after
// that: fixed in PRRTE's source (odls_base_default_kill_local_procs), no
// parameter changes it. On a loaded machine or under the sanitizers a
// rank's save may not fit in that: then what it saved before stays, its
// temporary file stays too, and the resume removes that with a note.
// Open MPI 4.1 gives the ranks about 1 s after each signal.
bool launcher_may_cut_the_save() { return open_mpi_major() >= 5; }

// The temporary files (NAME.tmp-PID) in `dirs`.
std::vector<fs::path> temporaries(const std::vector<fs::path>& dirs) {
  std::vector<fs::path> out;
  for (const fs::path& dir : dirs) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
      if (e.path().filename().string().find(".tmp-") != std::string::npos) out.push_back(e.path());
  }
  return out;
}

// A save the launcher cut (launcher_may_cut_the_save) leaves temporaries of
// processes that are gone, never a complete-looking file: the resume
// (`resume_err`) must remove each with a note.
void expect_only_dead_temporaries(const std::vector<fs::path>& left, const std::string& resume_err) {
  for (const fs::path& f : left) {
    EXPECT_NE(resume_err.find("note: removed " + f.string()), std::string::npos) << resume_err;
    EXPECT_FALSE(fs::exists(f)) << f << " outlived the resume";
  }
}

const std::vector<std::string> kEvery = {"--checkpoint-every", "0.2"};
// Long enough that only a hold or a signal saves: what is on disk is what
// the signal path put there.
const std::vector<std::string> kRarely = {"--checkpoint-every", "1000"};

// "resuming: K of 64 samples ..." -> K (-1 when absent).
long restored_count(const std::string& err) {
  const std::size_t at = err.find("resuming: ");
  return at == std::string::npos ? -1 : std::stol(err.substr(at + 10));
}

// Waits until `ranks` ranks hold (their held-rankR files); the run's own
// messages explain a run that never gets there. The limit only guards
// against a hang: the sanitized suite (ctest -j2) on a fresh Debian 13 took
// more than 60 s to bring its second rank to 15 samples.
void await_held(const fs::path& checkpoint, int ranks, const Background& run) {
  ASSERT_TRUE(
      wait_for([&] { return static_cast<int>(held_ranks(checkpoint).size()) >= ranks; }, 300s))  // under ctest's 600 s
      << "the ranks never held: " << run.err();
}

// The samples the pilot (8) and `ranks` holds after `after` samples hold.
constexpr long held_total(int ranks, int after) { return 8 + ranks * after; }

TEST_F(Checkpoint, KillNineOfMpirunOrOfOneRankThenResumeOnOtherRankCountsIsBitwiseIdentical) {
  struct Case {
    const char* what;
    int ranks, resume_ranks, hold;
    bool one_rank;  // SIGKILL one rank instead of mpirun: the launcher stops the others
    bool unsaved;   // the holds save nothing: what survives is what the stop signal saved
  };
  const Case cases[] = {
      {"mpirun killed right after the pilot, resumed on 3 ranks", 2, 3, 0, false, false},
      {"mpirun killed mid-sweep, resumed alone (1 rank)", 2, 1, 4, false, false},
      {"one rank killed mid-sweep: the survivors save on the launcher's SIGTERM; resumed on 2 ranks", 3, 2, 4, true,
       true},
  };
  int index = 0;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    const fs::path out = fresh_output("kill" + std::to_string(index++));
    const fs::path ckpt = out.string() + ".checkpoint";
    long expected = held_total(c.ranks, c.hold);
    {
      Background run(job_, out, held_run(c.ranks, c.unsaved ? kRarely : kEvery, c.hold, c.unsaved),
                     dir_.path() / "capture_bg");
      await_held(ckpt, c.ranks, run);
      const std::vector<Held> held = held_ranks(ckpt);
      if (c.one_rank) {
        ::kill(held.back().pid, SIGKILL);
        expected = 0;  // the victim saved nothing; each survivor saves what it kept
        for (std::size_t k = 0; k + 1 < held.size(); ++k) expected += held[k].kept;
      } else {
        ::kill(run.pid(), SIGKILL);
      }
      const int code = run.wait();
      std::printf("[%s] killed run: exit %d\n", c.what, code);
      ASSERT_NE(code, 0) << "the run finished before the kill: the case tests nothing";
    }
    ASSERT_TRUE(run_is_gone(out)) << "processes of the killed run live on";
    EXPECT_FALSE(fs::exists(out)) << "a killed run must not leave the output";
    const std::vector<fs::path> left = temporaries({out.parent_path(), ckpt});
    const auto r =
        run_ensemble(c.resume_ranks, job_, out, dir_.path() / "capture", {"--resume", "--checkpoint-every", "0.2"});
    std::printf("[%s] resume: exit %d, %s", c.what, r.exit_code, r.err.c_str());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    if (c.one_rank && launcher_may_cut_the_save()) {  // the survivors' saves on SIGTERM may be cut
      EXPECT_GE(restored_count(r.err), 0) << r.err;
      EXPECT_LE(restored_count(r.err), expected) << r.err;
      expect_only_dead_temporaries(left, r.err);
    } else {
      EXPECT_EQ(restored_count(r.err), expected) << r.err;
    }
    expect_like_reference(out, c.what);
    // Done: the checkpoint and every temporary are gone.
    EXPECT_EQ(listing(out.parent_path()), std::vector<std::string>{"ensemble.h5"});
  }
}

// The clean stop's marker cannot be written (its rename fails with EIO,
// tests/support/io_faults.c): the stop is still clean (exit 5, the line
// printed), a warning names the marker, nothing of it is left in the
// checkpoint, and --resume gives the uninterrupted run's bits.
TEST_F(Checkpoint, AStopMarkerThatCannotBeWrittenIsAWarningAndTheStopStaysClean) {
  const fs::path out = fresh_output("unmarked_stop");
  const fs::path ckpt = out.string() + ".checkpoint";
  {
    Launch launch = held_run(2, kRarely, 2);
    launch.environment = io_faults(dir_.path() / "fsyncs_unmarked", ckpt / "stopped");
    Background run(job_, out, launch, dir_.path() / "capture_unmarked");
    await_held(ckpt, 2, run);
    ::kill(run.pid(), SIGUSR1);
    EXPECT_EQ(run.wait(), 5) << run.err();
    EXPECT_NE(run.err().find("interrupted by SIGUSR1 after "), std::string::npos) << run.err();
    EXPECT_NE(run.err().find("(the marker of a clean stop)"), std::string::npos) << run.err();
    EXPECT_NE(run.err().find("warning: "), std::string::npos) << run.err();
  }
  for (const std::string& name : listing(ckpt)) EXPECT_EQ(name.find("stopped"), std::string::npos) << name;
  const auto resumed = run_ensemble(2, job_, out, dir_.path() / "capture", {"--resume"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  expect_like_reference(out, "resumed after a stop whose marker could not be written");
}

// One output, one owner: while a run holds its output (held 2 samples past
// the pilot), a second run on it, alone and on 2 ranks, with and without
// --resume, is refused at once (exit 2) naming the first's rank 0 and
// touching nothing of it; the first, stopped (SIGUSR1) and resumed, is the
// uninterrupted run bit for bit. Then the finished output submitted again
// with --resume: nothing is recomputed (exit 0, "nothing to do").
TEST_F(Checkpoint, ASecondRunOnOneOutputIsRefusedAtOnceAndTheFinishedOutputIsNotRecomputed) {
  const fs::path out = fresh_output("two_runs");
  const fs::path ckpt = out.string() + ".checkpoint";
  {
    Background first(job_, out, held_run(2, kRarely, 2), dir_.path() / "capture_first");
    await_held(ckpt, 2, first);
    const pid_t holder = held_ranks(ckpt).front().pid;
    const std::vector<std::string> before = listing(ckpt);
    for (const auto& [ranks, extra] :
         std::vector<std::pair<int, std::vector<std::string>>>{{0, {}}, {2, {"--resume"}}}) {
      const CommandResult second = run_ensemble(ranks, job_, out, dir_.path() / "capture_second", extra);
      std::printf("second run on %d ranks: exit %d in %.2f s\n", ranks, second.exit_code, second.seconds);
      EXPECT_EQ(second.exit_code, 2) << second.err;
      EXPECT_NE(second.err.find("ensemble.h5 is another run's output (host "), std::string::npos) << second.err;
      EXPECT_NE(second.err.find("pid " + std::to_string(holder) + ","), std::string::npos) << second.err;
      EXPECT_EQ(listing(ckpt), before) << "the refused run touched the first's checkpoint";
    }
    ::kill(first.pid(), SIGUSR1);  // forwarded by mpirun: a clean stop
    EXPECT_EQ(first.wait(), 5) << first.err();
    // Rank 0's line, also as a file for scripts whose mpirun hides it.
    const std::string marker = read_text(ckpt / "stopped");
    EXPECT_EQ(marker.rfind("interrupted by SIGUSR1 after ", 0), 0u) << marker;
    EXPECT_NE(first.err().find(marker), std::string::npos) << "the same line as printed: " << marker;
  }
  const auto resumed = run_ensemble(2, job_, out, dir_.path() / "capture", {"--resume"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  expect_like_reference(out, "held while a second run was refused, then resumed");
  const auto modified = fs::last_write_time(out);
  const auto again = run_ensemble(2, job_, out, dir_.path() / "capture", {"--resume"});
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.err.find("ensemble.h5 is this job's ensemble, complete, and there is no checkpoint to resume: "
                           "nothing to do"),
            std::string::npos)
      << again.err;
  EXPECT_EQ(fs::last_write_time(out), modified) << "the finished output was written again";
  EXPECT_EQ(listing(out.parent_path()), std::vector<std::string>{"ensemble.h5"});
  // Another job's output is refused, not overwritten.
  const fs::path other = dir_.path() / "other.toml";
  write_text(other, read_text(job_) + "\n# another job\n");
  const auto refused = run_ensemble(0, other, out, dir_.path() / "capture", {"--resume"});
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("is another job's output (its job text differs)"), std::string::npos) << refused.err;
  EXPECT_EQ(fs::last_write_time(out), modified);
}

// The paths a message puts in backticks: what its advice says to remove.
std::vector<fs::path> quoted_paths(const std::string& message) {
  std::vector<fs::path> paths;
  for (std::size_t at = message.find('`'); at != std::string::npos; at = message.find('`', at + 1)) {
    const std::size_t end = message.find('`', at + 1);
    if (end == std::string::npos) break;
    paths.emplace_back(message.substr(at + 1, end - at - 1));
    at = end;
  }
  return paths;
}

void flip_a_byte(const fs::path& file, std::uintmax_t at) {
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  f.seekg(static_cast<std::streamoff>(at));
  const char c = static_cast<char>(f.get());
  f.seekp(static_cast<std::streamoff>(at));
  f.put(static_cast<char>(c ^ 0x5a));
}

// Every "damaged" message names what to remove, and doing exactly that
// works: the next --resume runs, restores what is left, and ends bitwise
// the uninterrupted run. A checkpoint of two generations (a run stopped,
// resumed, stopped again: base-1 and part-1-rankR) is damaged one way per
// case, in a copy of its own.
TEST_F(Checkpoint, EveryDamagedMessagesAdviceFollowedLeadsToAWorkingRun) {
  const fs::path made = fresh_output("damaged_source");
  const fs::path ckpt = made.string() + ".checkpoint";
  for (int round = 0; round < 2; ++round) {
    std::vector<std::string> extra = kRarely;
    if (round == 1) extra.push_back("--resume");
    fs::remove(ckpt / "held-rank0");
    fs::remove(ckpt / "held-rank1");
    Background run(job_, made, held_run(2, extra, 3), dir_.path() / "capture_bg");
    await_held(ckpt, 2, run);
    ::kill(run.pid(), SIGUSR1);
    ASSERT_EQ(run.wait(), 5) << run.err();
  }
  ASSERT_TRUE(fs::exists(ckpt / "base-1.records"));
  ASSERT_TRUE(fs::exists(ckpt / "part-1-rank1.records"));
  struct Case {
    const char* what;
    std::function<void(const fs::path&)> damage;
  };
  // clang-format off
  const Case cases[] = {
      {"a part's records cut short", [](const fs::path& d) { fs::resize_file(d / "part-1-rank1.records", fs::file_size(d / "part-1-rank1.records") - 9); }},
      {"a part's state with a byte changed", [](const fs::path& d) { flip_a_byte(d / "part-1-rank0.state", fs::file_size(d / "part-1-rank0.state") / 2); }},
      {"a part's records removed alone", [](const fs::path& d) { fs::remove(d / "part-1-rank1.records"); }},
      {"the base's records with a byte changed", [](const fs::path& d) { flip_a_byte(d / "base-1.records", 40); }},
      {"common.state with a byte changed", [](const fs::path& d) { flip_a_byte(d / "common.state", 60); }},
  };
  // clang-format on
  int index = 0;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    const fs::path out = fresh_output("damaged" + std::to_string(index++));
    const fs::path copy = out.string() + ".checkpoint";
    fs::copy(ckpt, copy, fs::copy_options::recursive);
    fs::remove(copy / "held-rank0");
    fs::remove(copy / "held-rank1");
    c.damage(copy);
    const auto refused = run_ensemble(2, job_, out, dir_.path() / "capture", {"--resume"});
    std::printf("[%s] exit %d: %s", c.what, refused.exit_code, refused.err.c_str());
    EXPECT_EQ(refused.exit_code, 2);
    const std::vector<fs::path> remove = quoted_paths(refused.err);
    ASSERT_FALSE(remove.empty()) << "no advice: " << refused.err;
    for (const fs::path& p : remove) {
      EXPECT_TRUE(fs::exists(p)) << "the advice names a path that is not there: " << p;
      fs::remove_all(p);
    }
    const auto resumed = run_ensemble(2, job_, out, dir_.path() / "capture", {"--resume"});
    ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
    expect_like_reference(out, c.what);
  }
}

// Two generations: a resumed run is killed too, and resumed again.
// Units (hdf5/unit_chunks.hpp), forced to 4 rows on this small job: a
// stop in the middle of every sender's unit drops what it holds (the
// output goes; the checkpoint has them); the resumed run sends as units
// only those with no restored sample, and the output is the uninterrupted
// run's (2 ranks, no units) bit for bit.
TEST_F(Checkpoint, UnitsCutShortByAStopAndResumedGiveTheSameBits) {
  const fs::path out = fresh_output("units");
  const fs::path ckpt = out.string() + ".checkpoint";
  std::vector<std::string> extra = kRarely;
  extra.insert(extra.end(), {"--test-unit-rows", "4"});
  {
    Background run(job_, out, held_run(3, extra, 5), dir_.path() / "capture_bg");
    await_held(ckpt, 3, run);
    ::kill(run.pid(), SIGUSR1);
    ASSERT_EQ(run.wait(), 5) << run.err();
  }
  extra.push_back("--resume");
  const auto resumed = run_ensemble(3, job_, out, dir_.path() / "capture", extra);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  expect_like_reference(out, "units, stopped and resumed");
  H5File f(out);
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(read_integer_attribute(f.id(), "unit_rows"), 4);
  EXPECT_GE(read_integer_attribute(f.id(), "samples_in_units"), 4) << "the resumed run sent no unit";
}

TEST_F(Checkpoint, AResumedRunKilledAgainResumesAgain) {
  const fs::path out = fresh_output("twice");
  const fs::path ckpt = out.string() + ".checkpoint";
  for (int round = 0; round < 2; ++round) {
    std::vector<std::string> extra = kEvery;
    if (round == 1) extra.push_back("--resume");
    fs::remove(ckpt / "held-rank0");
    fs::remove(ckpt / "held-rank1");
    Background run(job_, out, held_run(2, extra, 4), dir_.path() / "capture_bg");
    await_held(ckpt, 2, run);
    ::kill(run.pid(), SIGKILL);
    ASSERT_NE(run.wait(), 0);
    ASSERT_TRUE(run_is_gone(out));
  }
  EXPECT_TRUE(fs::exists(ckpt / "base-1.state")) << "the first resume consolidated nothing";
  const auto r = run_ensemble(3, job_, out, dir_.path() / "capture", {"--resume"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(restored_count(r.err), held_total(2, 4) + 2 * 4) << r.err;
  expect_like_reference(out, "resumed twice");
}

// A stop signal, however it comes: exit 5 from the ranks, the hint with the
// number of samples kept, no temporary file, and every finished sample on
// disk, saved by the signal itself (the holds save nothing and the periodic
// checkpoints are 1000 s apart), so the resume restores exactly them.
struct SignalCase {
  const char* what;
  int ranks;  // 0: the binary alone
  int signal_number;
  enum class To { ranks, launcher, timeout, terminal } to;
  int exit_code;  // what the first process returns (mpirun, timeout, script or the binary); -1: mpirun's own, not 0
  std::vector<std::string> timeout_words = {};
  bool launcher_ends_job = false;  // mpirun itself takes SIGINT or SIGTERM and ends the job
};

void Checkpoint::expect_clean_stop(const SignalCase& c, int index) {
  SCOPED_TRACE(c.what);
  const fs::path out = fresh_output("signal" + std::to_string(index));
  const fs::path ckpt = out.string() + ".checkpoint";
  Launch launch = held_run(c.ranks, kRarely, 4, true);
  if (c.to == SignalCase::To::timeout) launch.wrapper = c.timeout_words;
  launch.pty = c.to == SignalCase::To::terminal;
  const fs::path fsync_log = dir_.path() / ("fsyncs_signal" + std::to_string(index));
  launch.environment = io_faults(fsync_log);
  Background run(job_, out, launch, dir_.path() / "capture_bg");
  await_held(ckpt, std::max(c.ranks, 1), run);
  if (c.to == SignalCase::To::ranks)
    for (const Held& h : held_ranks(ckpt)) ::kill(h.pid, c.signal_number);
  else if (c.to == SignalCase::To::terminal)
    run.type("\x03");  // Ctrl-C: SIGINT to the terminal's foreground process group
  else
    ::kill(run.pid(), c.signal_number);  // mpirun, the binary alone, or `timeout` (SIGALRM: its time is up)
  const int code = run.wait();
  const std::string err = run.err();
  std::printf("[%s] exit %d: %s\n", c.what, code, err.c_str());
  const long kept = held_total(std::max(c.ranks, 1), 4);
  if (!c.launcher_ends_job || launcher_forwards_last_words()) {
    EXPECT_NE(err.find("interrupted by "), std::string::npos) << err;
    EXPECT_NE(err.find(" after " + std::to_string(kept) + " of 64 samples; resume with --resume"), std::string::npos)
        << err;
  }
  if (c.exit_code >= 0)
    EXPECT_EQ(code, c.exit_code) << err;
  else
    EXPECT_NE(code, 0) << err;
  ASSERT_TRUE(run_is_gone(out)) << "processes of the stopped run live on";
  // The stop's save, made without a flush, flushed in place by every rank
  // once rank 0's message is out (unless the launcher cut the job short).
  if (!c.launcher_ends_job) expect_each_rank_flushed_its_state(fsync_log, c.ranks);
  // Nothing half-written: only the checkpoint directory (and the temporaries
  // of a save the launcher cut, where it may).
  const bool may_cut = c.launcher_ends_job && launcher_may_cut_the_save();
  const std::vector<fs::path> left = temporaries({out.parent_path(), ckpt});
  if (!may_cut) {
    EXPECT_EQ(left, std::vector<fs::path>{});
  }
  std::vector<std::string> kept_files = listing(out.parent_path());
  std::erase_if(kept_files, [](const std::string& f) { return f.find(".tmp-") != std::string::npos; });
  EXPECT_EQ(kept_files, std::vector<std::string>{"ensemble.h5.checkpoint"});
  const auto r = run_ensemble(c.ranks == 0 ? 0 : 3, job_, out, dir_.path() / "capture", {"--resume"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  if (may_cut) {
    std::printf("[%s] %zu temporaries left, %ld of %ld samples restored\n", c.what, left.size(), restored_count(r.err),
                kept);
    EXPECT_GE(restored_count(r.err), 0) << r.err;  // the resume says what it restored
    EXPECT_LE(restored_count(r.err), kept) << r.err;
    expect_only_dead_temporaries(left, r.err);
  } else {
    EXPECT_EQ(restored_count(r.err), kept) << r.err;
  }
  expect_like_reference(out, std::string("resumed after ") + c.what);
}

TEST_F(Checkpoint, SigtermAndSigintGiveExitFiveAMessageAndACheckpointAndNoTemporary) {
  const SignalCase cases[] = {{"SIGTERM to every rank (as Slurm does)", 2, SIGTERM, SignalCase::To::ranks, 5},
                              {"SIGINT to the binary alone (Ctrl-C)", 0, SIGINT, SignalCase::To::launcher, 5},
                              {"SIGUSR1 to mpirun (forwarded to the ranks)", 2, SIGUSR1, SignalCase::To::launcher, 5}};
  int index = 0;
  for (const SignalCase& c : cases) expect_clean_stop(c, index++);
}

// Ctrl-C and SIGTERM make mpirun itself exit non-zero (Open MPI 4.1: 1);
// `timeout` exits 124 when its time is up. What the ranks do is the same
// in every case: they stop cleanly and keep every finished sample. A plain
// `timeout` signals mpirun twice (itself and its process group), which
// Open MPI takes as "kill now": docs/cluster.md says to give it -s USR1 or
// --foreground, the two tested here (SIGALRM is how its time comes up).
TEST_F(Checkpoint, CtrlCInATerminalAndSigtermToMpirunOrTimeoutStopCleanly) {
  // clang-format off
  const SignalCase cases[] = {
      {"Ctrl-C typed at mpirun's terminal", 2, SIGINT, SignalCase::To::terminal, -1, {}, true},
      {"SIGTERM to mpirun", 2, SIGTERM, SignalCase::To::launcher, -1, {}, true},
      {"the time of `timeout -s USR1 600 mpirun` is up", 2, SIGALRM, SignalCase::To::timeout, 124,
       {"timeout", "-s", "USR1", "600"}},
      {"the time of `timeout --foreground 600 mpirun` is up", 2, SIGALRM, SignalCase::To::timeout, 124,
       {"timeout", "--foreground", "600"}, true}};
  // clang-format on
  int index = 10;
  for (const SignalCase& c : cases) expect_clean_stop(c, index++);
}

TEST_F(Checkpoint, ACheckpointOfAnotherJobIsRefusedAndAFreshRunDoesNotOverwriteOne) {
  const fs::path out = fresh_output("other");
  const fs::path ckpt = out.string() + ".checkpoint";
  {
    Background run(job_, out, held_run(2, kEvery, 4), dir_.path() / "capture_bg");
    await_held(ckpt, 2, run);
    ::kill(run.pid(), SIGKILL);
    run.wait();
  }
  ASSERT_TRUE(run_is_gone(out));
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

// The output fails at its very last step, the rename into place (EIO from
// tests/support/io_faults.c): exit 4 with the file named, no output and no
// temporary, and the run's last save (RankResults::finish), flushed on
// every rank, holds every sample: --resume restores all 64 and writes the
// uninterrupted run's bits. In a run that ends well, too, every rank's last
// save reaches the disk (its flush overlaps the output's writing), the last
// rank's made 0.5 s slower: rank 0 removes the checkpoint only after it.
TEST_F(Checkpoint, AFailedFinalWriteLeavesEverySampleForResume) {
  const auto launch = [&](int ranks, const fs::path& out, const fs::path& fsync_log, const fs::path& fail_rename) {
    std::vector<std::string> prefix = io_faults(fsync_log, fail_rename);
    prefix.insert(prefix.begin(), "env");
    prefix.push_back("TREEDYN_TEST_SLOW_FSYNC=-rank" + std::to_string(std::max(ranks, 1) - 1) + ".state");
    prefix.insert(prefix.end(), {"timeout", "-k", "10", std::to_string(kTimeoutSeconds)});
    if (ranks > 0) prefix.insert(prefix.end(), {TREEDYN_MPIEXEC, "--oversubscribe", "-np", std::to_string(ranks)});
    return run_command(TREEDYN_ENSEMBLE_BINARY, {job_.string(), "-o", out.string(), "-q"}, dir_.path() / "capture",
                       prefix);
  };
  for (int ranks : {0, 2}) {
    SCOPED_TRACE(describe(ranks));
    const fs::path out = fresh_output("final_write_" + std::to_string(ranks));
    const fs::path failed_log = dir_.path() / ("fsyncs_failed_" + std::to_string(ranks));
    const auto failed = launch(ranks, out, failed_log, out);
    std::printf("[final write fails, %s] exit %d: %s", describe(ranks).c_str(), failed.exit_code, failed.err.c_str());
    EXPECT_EQ(failed.exit_code, 4) << failed.err;
    EXPECT_NE(failed.err.find("error: output " + out.string() +
                              ": cannot rename the finished file into place "
                              "(Input/output error)"),
              std::string::npos)
        << failed.err;
    EXPECT_EQ(listing(out.parent_path()), std::vector<std::string>{"ensemble.h5.checkpoint"})
        << "no output, no temporary: only the checkpoint";
    expect_each_rank_flushed_its_state(failed_log, ranks);

    const auto resumed = run_ensemble(2, job_, out, dir_.path() / "capture", {"--resume"});
    ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
    EXPECT_EQ(restored_count(resumed.err), 64) << resumed.err;
    expect_like_reference(out, "resumed after a failed final write, " + describe(ranks));

    const fs::path well = fresh_output("ends_well_" + std::to_string(ranks));
    const fs::path well_log = dir_.path() / ("fsyncs_well_" + std::to_string(ranks));
    const auto ends_well = launch(ranks, well, well_log, {});
    ASSERT_EQ(ends_well.exit_code, 0) << ends_well.err;
    EXPECT_EQ(ends_well.err.find("warning"), std::string::npos) << ends_well.err;
    EXPECT_EQ(listing(well.parent_path()), std::vector<std::string>{"ensemble.h5"});
    expect_each_rank_flushed_its_state(well_log, ranks);
  }
}

}  // namespace

// A run that stops itself, killed in its second wave (and, on two ranks,
// in its first), resumes to the same stop: the decisions after each wave
// are replayed from the restored records.
TEST_F(Checkpoint, AStoppingRunKilledMidWayResumesToTheSameStop) {
  const fs::path job = dir_.path() / "stopping.toml";
  write_text(job, spin_exceedance_job(3000, true));
  const fs::path reference = fresh_output("stop_reference");
  const auto full = run_ensemble(2, job, reference, dir_.path() / "capture_ref", {"--checkpoint-every", "0"});
  ASSERT_EQ(full.exit_code, 0) << full.err;
  struct Case {
    const char* what;
    int ranks, resume_ranks, hold;
  };
  const Case cases[] = {{"alone, killed after 150 samples past the pilot (wave 2), resumed on 3 ranks", 0, 3, 150},
                        {"2 ranks killed after 15 samples each past the pilot, resumed alone", 2, 0, 15}};
  int index = 0;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    const fs::path out = fresh_output("stop_kill" + std::to_string(index++));
    const fs::path ckpt = out.string() + ".checkpoint";
    {
      Background run(job, out, held_run(c.ranks, kEvery, c.hold), dir_.path() / "capture_bg");
      await_held(ckpt, std::max(c.ranks, 1), run);
      ::kill(run.pid(), SIGKILL);
      ASSERT_NE(run.wait(), 0) << "the run finished before the kill: the case tests nothing";
    }
    ASSERT_TRUE(run_is_gone(out)) << "processes of the killed run live on";
    const auto r = run_ensemble(c.resume_ranks, job, out, dir_.path() / "capture", {"--resume"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(restored_count(r.err), 32 + std::max(c.ranks, 1) * c.hold) << r.err;
    H5File a(reference), b(out);
    EXPECT_EQ(read_integer_attribute(b.id(), "samples_used"), read_integer_attribute(a.id(), "samples_used"));
    EXPECT_LT(read_integer_attribute(b.id(), "samples_used"), 3000);
    expect_identical_datasets(a.id(), "uninterrupted", b.id(), c.what, {"/stats", "/samples", "/responses"});
  }
}

// A subset simulation killed inside a chain of its first later level
// resumes to the same levels, bit for bit: rank 0 replays the decisions
// from the restored records, and the chain cut short runs again from its
// seed (its finished runs give the same responses and are not kept twice).
TEST_F(Checkpoint, ASubsetSimulationKilledInsideAChainResumesToTheSameLevels) {
  const fs::path job = dir_.path() / "ball.toml";
  write_text(job, isotropic_ball_job(ball_limit_for(1e-3), 1000, kBallSubset));
  const fs::path reference = fresh_output("subset_reference");
  const auto full = run_ensemble(2, job, reference, dir_.path() / "capture_ref", {"--checkpoint-every", "0"});
  ASSERT_EQ(full.exit_code, 0) << full.err;
  const fs::path out = fresh_output("subset_kill");
  const fs::path ckpt = out.string() + ".checkpoint";
  constexpr int kHold = 968 + 105;  // the rest of level 0 after its 32 pilot runs, then into chain 11 of level 1
  {
    Background run(job, out, held_run(0, kEvery, kHold), dir_.path() / "capture_bg");
    await_held(ckpt, 1, run);
    ::kill(run.pid(), SIGKILL);
    ASSERT_NE(run.wait(), 0) << "the run finished before the kill: the case tests nothing";
  }
  ASSERT_TRUE(run_is_gone(out)) << "processes of the killed run live on";
  const auto r = run_ensemble(2, job, out, dir_.path() / "capture", {"--resume"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(restored_count(r.err), 32 + kHold) << r.err;
  H5File a(reference), b(out);
  expect_identical_datasets(a.id(), "uninterrupted", b.id(), "killed in a chain and resumed",
                            {"/stats", "/samples", "/responses", "/rare_event"});
}
