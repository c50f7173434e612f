// One output, one owner (process/output_lock.*). fcntl locks belong to a
// process, so every contender here is a child process (fork); each child
// reports through its exit code and a file, never through timing.
#include "process/output_lock.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "process/atomic_file.hpp"
#include "support/command.hpp"

namespace {

using namespace treedyn::process;
using treedyn::testing::read_text;
using treedyn::testing::TempDir;
namespace fs = std::filesystem;

constexpr int kTook = 10, kRefused = 11, kOther = 12;

// A child that tries to take the lock and exits kTook / kRefused, with the
// refusal's message in `message`.
int try_in_child(const fs::path& out, const fs::path& message, OutputLock::Mode mode = OutputLock::Mode::automatic) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    try {
      OutputLock lock(out, "child", mode);
      ::_exit(kTook);
    } catch (const OutputLocked& e) {
      std::ofstream(message) << e.what();
      ::_exit(kRefused);
    } catch (...) {
      ::_exit(kOther);
    }
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(OutputLock, ASecondRunIsRefusedNamingTheHolderAndTheLockGoesWithItsOwner) {
  TempDir dir("output_lock");
  const fs::path out = dir.path() / "run.h5";
  {
    OutputLock lock(out, "treedyn-ensemble job.toml -o run.h5");
    EXPECT_STREQ(lock.kind(), "fcntl");
    EXPECT_TRUE(fs::exists(dir.path() / "run.h5.lock"));
    EXPECT_EQ(try_in_child(out, dir.path() / "message"), kRefused);
    const std::string message = read_text(dir.path() / "message");
    EXPECT_NE(message.find("run.h5 is another run's output (host "), std::string::npos) << message;
    EXPECT_NE(message.find("pid " + std::to_string(::getpid())), std::string::npos) << message;
    EXPECT_NE(message.find(": treedyn-ensemble job.toml -o run.h5)"), std::string::npos) << message;
    EXPECT_NE(message.find("then run this again with --resume"), std::string::npos) << message;
  }
  EXPECT_FALSE(fs::exists(dir.path() / "run.h5.lock")) << "removed by its owner";
  EXPECT_EQ(try_in_child(out, dir.path() / "message"), kTook);
}

// A holder killed with SIGKILL leaves its file, but the kernel dropped its
// lock: the next run takes it without any hand work.
TEST(OutputLock, AKilledHoldersLockIsTakenWithoutHandWork) {
  TempDir dir("output_lock");
  const fs::path out = dir.path() / "run.h5", ready = dir.path() / "ready";
  const pid_t holder = ::fork();
  if (holder == 0) {
    OutputLock lock(out, "holder");
    std::ofstream(ready) << "locked";
    ::pause();
    ::_exit(0);
  }
  while (!fs::exists(ready)) ::usleep(1000);  // the holder says when it holds the lock
  EXPECT_EQ(try_in_child(out, dir.path() / "message"), kRefused);
  ::kill(holder, SIGKILL);
  ::waitpid(holder, nullptr, 0);
  EXPECT_TRUE(fs::exists(dir.path() / "run.h5.lock")) << "SIGKILL leaves the file";
  EXPECT_EQ(try_in_child(out, dir.path() / "message"), kTook);
}

// Without record locks: the exclusive file. A live holder refuses, with how
// to tell a stale lock and the command that clears it; one left by a
// process of this host that no longer runs is taken over; one from another
// host is refused.
TEST(OutputLock, TheExclusiveFileFallbackTakesOverADeadHoldersLockOfThisHostOnly) {
  TempDir dir("output_lock");
  const fs::path out = dir.path() / "run.h5", lock_file = dir.path() / "run.h5.lock";
  {
    OutputLock lock(out, "first", OutputLock::Mode::exclusive_file);
    EXPECT_STREQ(lock.kind(), "exclusive file");
    EXPECT_EQ(try_in_child(out, dir.path() / "message", OutputLock::Mode::exclusive_file), kRefused);
    const std::string message = read_text(dir.path() / "message");
    EXPECT_NE(message.find("the lock is stale and `rm " + lock_file.string() + "` clears it"), std::string::npos)
        << message;
  }
  EXPECT_FALSE(fs::exists(lock_file));
  char host[256] = "";
  ::gethostname(host, sizeof host - 1);
  const pid_t dead = ::fork();  // a process that no longer runs
  if (dead == 0) ::_exit(0);
  ::waitpid(dead, nullptr, 0);
  std::ofstream(lock_file) << "host=" << host << "\npid=" << dead << "\njob=\nstarted=x\ncommand=killed\n";
  EXPECT_EQ(try_in_child(out, dir.path() / "message", OutputLock::Mode::exclusive_file), kTook);
  std::ofstream(lock_file) << "host=elsewhere.example\npid=" << dead << "\njob=4242\nstarted=x\ncommand=other\n";
  EXPECT_EQ(try_in_child(out, dir.path() / "message", OutputLock::Mode::exclusive_file), kRefused);
  const std::string message = read_text(dir.path() / "message");
  EXPECT_NE(message.find("if squeue -j 4242 shows nothing and no process"), std::string::npos) << message;
}

TEST(OutputLock, AMissingDirectoryIsAFileError) {
  TempDir dir("output_lock");
  EXPECT_THROW(OutputLock(dir.path() / "missing" / "run.h5", "x"), FileError);
}

}  // namespace
