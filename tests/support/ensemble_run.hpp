// Running treedyn-ensemble from a test: alone or under mpirun, always under
// `timeout`. Header-only: the binaries' paths are compile definitions of
// each test executable (tests/CMakeLists.txt).
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>
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

// The text of a shipped job (jobs/NAME) with each `from` replaced by its `to`;
// throws when a `from` is missing, so a changed example fails loudly instead
// of silently testing the full job. Tests shorten the examples with it: what
// they check does not depend on 5 s of motion, and the sanitizer pass runs
// them again several times slower.
inline std::string edited_job_text(const std::string& name,
                                   const std::vector<std::pair<std::string, std::string>>& edits) {
  std::string text = read_text(std::filesystem::path(TREEDYN_JOBS_DIR) / name);
  for (const auto& [from, to] : edits) {
    const std::size_t at = text.find(from);
    if (at == std::string::npos) throw std::runtime_error(name + " changed: no '" + from + "'");
    text.replace(at, from.size(), to);
  }
  return text;
}

// A job with a known answer for stopping rules: the spherical pendulum over
// 0.05 s, Monte Carlo (or `design`) over at most `samples`, and as a response
// the spin at t = 0, which is the sampled input itself (uniform on
// [1.8, 2.2] rad/s), so P(spin0 > 2.19 rad/s) = 0.025. `with_stop` adds a
// rule that stops once that probability has a coefficient of variation of
// 0.2, checked every 100 samples.
inline std::string spin_exceedance_job(int samples, bool with_stop, const std::string& design = "monte_carlo") {
  std::string text = edited_job_text("spherical_pendulum.toml",
                                     {{"end_time = 10.0", "end_time = 0.05"},
                                      {"samples = 64", "samples = " + std::to_string(samples)},
                                      {"design = \"latin_hypercube\"", "design = \"" + design + "\""}});
  text += R"(
[[ensemble.response]]
name = "spin0"
quantity = "angular_velocity"
column = "rod.z"
reduce = "at_time"
time = 0.0
limit = 2.19
fail_if = "above"
)";
  if (with_stop) text += "\n[ensemble.stop]\nresponse = \"spin0\"\nexceedance_cov = 0.2\nevery = 100\n";
  return text;
}

// The sanitizer pass (TREEDYN_SANITIZE) runs every test but these, which
// run in the normal pass: the largest shipped examples whole (crane_payload,
// kapitza, y_tree: 130 s of the sanitized suite; their code paths run there
// on smaller jobs) and the report's figures beyond one example (Python's
// matplotlib, nothing the sanitizers check). Returns why, or "" to run.
inline std::string skipped_when_sanitized(const std::string& example, bool figures) {
#ifdef TREEDYN_SANITIZED
  if (figures && example != "spherical_pendulum")
    return "the sanitizer pass draws one example's figures (spherical_pendulum); the normal pass draws all";
  if (example == "crane_payload" || example == "kapitza" || example == "y_tree")
    return "the sanitizer pass runs the smaller examples whole; the normal pass runs all";
#else
  (void)example;
  (void)figures;
#endif
  return "";
}

inline std::string describe(int ranks) {
  return ranks == 0 ? std::string("the binary alone") : "mpirun -np " + std::to_string(ranks);
}

}  // namespace treedyn::testing
