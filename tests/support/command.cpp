#include "support/command.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <system_error>

namespace treedyn::testing {

namespace fs = std::filesystem;

TempDir::TempDir(const std::string& tag) {
  std::random_device rd;
  for (int attempt = 0; attempt < 100; ++attempt) {
    const fs::path p =
        fs::temp_directory_path() / ("treedyn_" + tag + "_" + std::to_string(getpid()) + "_" + std::to_string(rd()));
    std::error_code ec;
    if (fs::create_directory(p, ec)) {
      path_ = p;
      return;
    }
  }
  throw std::runtime_error("cannot create a temporary directory");
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

namespace {

// This test process's directory for the launchers' session directories,
// removed with everything in it when the process ends.
struct LauncherTemp {
  fs::path path = fs::temp_directory_path() / ("treedyn_mpi_" + std::to_string(getpid()));
  LauncherTemp() { fs::create_directories(path); }
  ~LauncherTemp() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

}  // namespace

std::string launcher_environment(bool mpirun) {
  // Open MPI refuses to run as root (as CI does) without these; they reach
  // mpirun, its ranks and a singleton treedyn-ensemble alike.
  setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
  setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  if (!mpirun) return "";  // a singleton's helper (Open MPI 4.1) may outlive this process
  static const LauncherTemp temp;
  return "TMPDIR=" + quote(temp.path.string());
}

CommandResult run_command(const std::string& binary, const std::vector<std::string>& args, const fs::path& capture,
                          const std::vector<std::string>& prefix) {
  fs::create_directories(capture);
  const fs::path out = capture / "stdout.txt", err = capture / "stderr.txt";
  const bool mpirun = std::find(prefix.begin(), prefix.end(), std::string(TREEDYN_MPIEXEC)) != prefix.end();
  std::string command = launcher_environment(mpirun) + " ";
  for (const auto& word : prefix) command += quote(word) + " ";
  command += quote(binary);
  for (const auto& a : args) command += " " + quote(a);
  command += " >" + quote(out.string()) + " 2>" + quote(err.string()) + " </dev/null";
  const auto start = std::chrono::steady_clock::now();
  const int status = std::system(command.c_str());
  CommandResult r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.exit_code = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_text(out);
  r.err = read_text(err);
  fs::remove(out);
  fs::remove(err);
  return r;
}

std::string position_of(const std::string& text, const std::string& needle, std::size_t skip) {
  const std::size_t at = text.find(needle);
  if (at == std::string::npos) throw std::invalid_argument("not in the job: " + needle);
  const std::size_t p = at + skip;
  const auto line = std::count(text.begin(), text.begin() + static_cast<long>(p), '\n') + 1;
  const std::size_t line_start = text.rfind('\n', p == 0 ? 0 : p - 1);
  const std::size_t column = line_start == std::string::npos || p == 0 ? p + 1 : p - line_start;
  return std::to_string(line) + ":" + std::to_string(column);
}

std::vector<std::string> lines_starting_with(const std::string& text, const std::string& prefix) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(prefix, 0) == 0) out.push_back(line);
  return out;
}

std::string value_position(const std::string& text, const std::string& key_and_value) {
  return position_of(text, key_and_value, key_and_value.find("= ") + 2);
}

}  // namespace treedyn::testing
