// Running treedyn-ensemble from a test: alone or under mpirun, always under
// `timeout`. Header-only: the binaries' paths are compile definitions of
// each test executable (tests/CMakeLists.txt).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "support/command.hpp"

namespace treedyn::testing {

// Seconds `timeout` gives each mpirun before killing it (then 10 s more
// before SIGKILL). A normal run here takes 0.3 - 3 s.
inline constexpr int kTimeoutSeconds = 120;

// Runs `treedyn-ensemble JOB -o OUTPUT -q`: alone when ranks == 0, else under
// `mpirun --oversubscribe -np RANKS`; always under `timeout`. stdout and stderr
// are captured in files under `capture` (not the output's directory, so that
// directory holds only what the ensemble writes).
inline CommandResult run_ensemble(int ranks, const std::filesystem::path& job,
                                  const std::filesystem::path& output,
                                  const std::filesystem::path& capture,
                                  const std::vector<std::string>& extra = {}) {
  std::vector<std::string> prefix = {"timeout", "-k", "10", std::to_string(kTimeoutSeconds)};
  if (ranks > 0)
    prefix.insert(prefix.end(),
                  {TREEDYN_MPIEXEC, "--oversubscribe", "-np", std::to_string(ranks)});
  std::vector<std::string> args = {job.string(), "-o", output.string(), "-q"};
  args.insert(args.end(), extra.begin(), extra.end());
  return run_command(TREEDYN_ENSEMBLE_BINARY, args, capture, prefix);
}

inline std::string describe(int ranks) {
  return ranks == 0 ? std::string("the binary alone") : "mpirun -np " + std::to_string(ranks);
}

}  // namespace treedyn::testing
