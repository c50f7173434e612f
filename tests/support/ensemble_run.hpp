// Running treedyn-ensemble from a test: alone or under mpirun, always under
// `timeout`. Header-only: the binaries' paths are compile definitions of
// each test executable (tests/CMakeLists.txt).
#pragma once

#include <boost/math/special_functions/gamma.hpp>

#include <cstdio>
#include <filesystem>
#include <optional>
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
inline CommandResult run_ensemble(int ranks, const std::filesystem::path& job, const std::filesystem::path& output,
                                  const std::filesystem::path& capture, const std::vector<std::string>& extra = {}) {
  std::vector<std::string> prefix = {"timeout", "-k", "10", std::to_string(kTimeoutSeconds)};
  if (ranks > 0) prefix.insert(prefix.end(), {TREEDYN_MPIEXEC, "--oversubscribe", "-np", std::to_string(ranks)});
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
  std::string text =
      edited_job_text("spherical_pendulum.toml", {{"end_time = 10.0", "end_time = 0.05"},
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

// The isotropic ball of tests/mpi/subset_test.cpp (its header says why the
// exceedance probability is exact): E0 = -4.905 J, E = E0 + 0.275 |w|^2.
inline constexpr double kBallE0 = -4.905, kBallHalfInertia = 0.275;

// The energy limit exceeded with `probability`: E0 + 0.275 c, c the
// chi-square (3 degrees of freedom) quantile.
inline double ball_limit_for(double probability) {
  return kBallE0 + kBallHalfInertia * 2.0 * boost::math::gamma_q_inv(1.5, probability);
}

// The job: w ~ N(0, I) rad/s as three inputs, the final total energy as the
// response with `limit`; `design_lines` go into [ensemble].
inline std::string isotropic_ball_job(double limit, int samples, const std::string& design_lines);

// The ball's job: `ensemble` lines under [ensemble] (samples, seed, design,
// ...), then `tables` (its [[ensemble.perturbation]] and
// [[ensemble.response]] tables as TOML text), over `end_time` seconds.
// Every test of the ball builds on it (subset simulation, the failure
// region, the rankings, the page's answers).
inline std::string ball_job_text(const std::string& ensemble, const std::string& tables, double end_time = 0.2) {
  char end[32];
  std::snprintf(end, sizeof end, "%g", end_time);
  return R"(title = "isotropic ball on a spherical joint"

[[body]]
name = "ball"
mass = 1.0
inertia = [[0.3, 0.0, 0.0], [0.0, 0.3, 0.0], [0.0, 0.0, 0.55]]
parent = "base"
joint_on_child = [0.0, 0.0, 0.5]

[integrator]
method = "cvode_adams"
parameterisation = "quaternion"
rtol = 1e-10
atol = 1e-12

[output]
end_time = )" +
         std::string(end) + R"(
step = 0.1
quantities = ["energy"]

[ensemble]
)" + ensemble +
         "\n" + tables;
}

// A normal perturbation of `target` with standard deviation `std`, and the
// final total energy as a response with an optional limit (exceeded above).
inline std::string normal_input(const std::string& target, double std) {
  char text[200];
  std::snprintf(text, sizeof text,
                "\n[[ensemble.perturbation]]\ntarget = \"%s\"\ndistribution = \"normal\"\nstd = %.17g\n",
                target.c_str(), std);
  return text;
}
inline std::string energy_response(const std::optional<double>& limit) {
  std::string text =
      "\n[[ensemble.response]]\nname = \"energy\"\nquantity = \"energy\"\ncolumn = \"total\"\n"
      "reduce = \"final\"\n";
  if (limit) {
    char value[64];
    std::snprintf(value, sizeof value, "%.17g", *limit);
    text += std::string("limit = ") + value + "\nfail_if = \"above\"\n";
  }
  return text;
}

inline std::string isotropic_ball_job(double limit, int samples, const std::string& design_lines) {
  return ball_job_text("samples = " + std::to_string(samples) + "\nseed = 5\n" + design_lines,
                       normal_input("body.ball.angular_velocity.x", 1.0) +
                           normal_input("body.ball.angular_velocity.y", 1.0) +
                           normal_input("body.ball.angular_velocity.z", 1.0) + energy_response(limit));
}

inline const std::string kBallSubset = "design = \"subset_simulation\"\n\n[ensemble.subset]\nresponse = \"energy\"";

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

// The same for a statistical check whose runs are many but whose code
// paths a smaller test of the sanitized pass runs too: `what` names it.
inline std::string skipped_when_sanitized_as_large(const std::string& what) {
#ifdef TREEDYN_SANITIZED
  return what + ": its code paths run in the sanitizer pass on smaller jobs; the normal pass runs it";
#else
  (void)what;
  return "";
#endif
}

// Bad input: `text` as a job is refused by `treedyn-ensemble --check` and by
// a run alike, with exit 2, "error: FILE:" first and every one of `words` in
// the message, and nothing written beside the job (only the job file and the
// capture directory stay in a fresh directory).
inline void expect_job_refused(const std::string& text, const std::vector<std::string>& words) {
  TempDir dir("refused_job");
  const std::filesystem::path job = dir.path() / "job.toml";
  write_text(job, text);
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"--check", job.string()},
        std::vector<std::string>{job.string(), "-o", (dir.path() / "out.h5").string()}}) {
    const CommandResult r = run_command(TREEDYN_ENSEMBLE_BINARY, args, dir.path() / "capture");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(r.err.rfind("error: " + job.string() + ":", 0), 0u) << r.err;
    for (const std::string& w : words) EXPECT_NE(r.err.find(w), std::string::npos) << w << "\n" << r.err;
  }
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, 2u) << "only the job and the capture directory";
}

inline std::string describe(int ranks) {
  return ranks == 0 ? std::string("the binary alone") : "mpirun -np " + std::to_string(ranks);
}

}  // namespace treedyn::testing
