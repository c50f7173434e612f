// Running the real binaries from tests: temporary directories, text files,
// shell quoting, a command run with its stdout and stderr captured, and the
// LINE:COL of a piece of a job's text (as error messages quote it).
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace treedyn::testing {

// A fresh directory under the system temp dir, treedyn_TAG_PID_RANDOM,
// removed with its contents on destruction.
class TempDir {
 public:
  explicit TempDir(const std::string& tag);
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

std::string read_text(const std::filesystem::path& p);
void write_text(const std::filesystem::path& p, const std::string& text);

// `s` in single quotes for /bin/sh.
std::string quote(const std::string& s);

struct CommandResult {
  int exit_code = -1;  // 124 (137 after SIGKILL): `timeout` stopped a hang
  std::string out, err;
  double seconds = 0.0;  // wall time of the whole command
};

// What every launch needs: Open MPI's permission to run as root (set in
// this process's environment, so it reaches mpirun, its ranks and a
// singleton alike), and for `mpirun`, a shell assignment to put before the
// command: TMPDIR in a directory of this test process that goes when it
// ends. Open MPI 5's mpirun keeps its session directory in TMPDIR, named by
// its PID; one it could not remove (a test kills mpirun with SIGKILL) makes a
// later mpirun that gets the same PID fail (PRTE "session_dir ... Exists",
// exit 213).
std::string launcher_environment(bool mpirun);

// Runs `PREFIX... BINARY ARGS...` through the shell, every word quoted, with
// stdin from /dev/null. `prefix` holds words that wrap the binary (a
// `timeout` line, an `mpirun -np N` line). stdout and stderr are captured in
// stdout.txt and stderr.txt under `capture` (created if missing), which are
// removed again after reading: a test can give a directory of its own, so
// the directories it inspects hold only what the binary writes.
CommandResult run_command(const std::string& binary, const std::vector<std::string>& args,
                          const std::filesystem::path& capture, const std::vector<std::string>& prefix = {});

// The lines of `text` that start with `prefix` (without their newline): a
// command's own messages among a launcher's.
std::vector<std::string> lines_starting_with(const std::string& text, const std::string& prefix);

// "LINE:COL" (1-based) of the first occurrence of `needle` in `text`, plus
// `skip` characters (to point inside it). Throws std::invalid_argument when
// `needle` is not in `text`.
std::string position_of(const std::string& text, const std::string& needle, std::size_t skip = 0);

// Where the value of `key = value` starts.
std::string value_position(const std::string& text, const std::string& key_and_value);

}  // namespace treedyn::testing
