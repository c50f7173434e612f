// Subset simulation (Au and Beck 2001) in standard normal space, as stated
// in docs/rare_events.md, section 3: P(g(u) > b) for u ~ N(0, I)
// through levels of conditional samples, each level's threshold the
// (1 - p0) quantile of the one before.
//
// The pieces are what a parallel driver hands out and gathers: level 0 is N
// points u_k; a later level is N p0 Markov chains of 1/p0 states, each
// chain run on its own (run_chain) from its seed; close_level, on all of a
// level's states in index order, fixes the next threshold and seeds. Every
// random number is keyed by (seed, run index, input), so the result does not
// depend on who runs which chain or in what order. subset_simulation() is
// the whole algorithm, serially, on those pieces.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace treedyn::designs {

struct SubsetSettings {
  std::uint64_t samples = 0;       // N: states per level (runs at level 0)
  double level_probability = 0.1;  // p0
  int max_levels = 10;             // levels after level 0, at most
  double limit = 0.0;              // b: failure when g > b
  std::uint64_t seed = 0;

  std::uint64_t chains() const;  // N_c = N p0
  std::uint64_t states() const;  // N_s = 1 / p0
};

// Empty when the settings are usable, else what is wrong and what is allowed.
std::string check(const SubsetSettings& settings);

// Run indices count runs only, level by level. Level 0: sample k is index
// k. Level j >= 1 makes R = N_c (N_s - 1) runs: chain c, state l >= 1 is
// N + (j - 1) R + c (N_s - 1) + l - 1. State 0 of a chain is its seed, a
// state of the level before, not a run.
struct RunPlace {
  int level = 0;
  std::uint64_t chain = 0;  // level 0: the sample
  std::uint64_t state = 0;  // level 0: 0; later levels: 1 .. N_s - 1
};
std::uint64_t run_index(const SubsetSettings& settings, const RunPlace& place);
RunPlace run_place(const SubsetSettings& settings, std::uint64_t index);
// Runs of levels 0 .. levels-1 (the first index of level `levels`).
std::uint64_t runs_before(const SubsetSettings& settings, int levels);

// Phi(u): the uniform number in (0, 1) of a standard normal coordinate,
// kept inside the open interval (the inputs' quantile functions are not
// finite at 0 and 1; Phi(u) rounds to 1 from u = 8.3 on).
double to_uniform(double u);

// Level 0's point k: u_i = Phi^-1(U(seed, k, i)).
void level_zero_point(const SubsetSettings& settings, std::uint64_t k, std::span<double> u);

// The proposal of conditional sampling (Papaioannou et al. 2015) for run
// `index` from state u: v_i = rho_i u_i + sqrt(1 - rho_i^2) e_i with
// rho_i = sqrt(1 - s_i^2) and e_i ~ N(0, 1) keyed by (seed, index, i). It
// leaves N(0, I) invariant.
void propose(const SubsetSettings& settings, std::uint64_t index, std::span<const double> spread,
             std::span<const double> u, std::span<double> v);

// One Markov chain of a level: its states u (N_s x D, row by row), their
// responses, and whether each state after the seed was an accepted
// proposal. Every proposal is a run; a rejected one repeats the state and
// its response.
struct Chain {
  std::vector<double> u;
  std::vector<double> g;
  std::vector<std::uint8_t> accepted;  // [0] (the seed) is 0
  std::uint64_t runs = 0;
  std::uint64_t failed_runs = 0;  // proposals whose run failed (rejected)
};

// g(index, u): the response of the run at `index` for the point u. A NaN
// (a failed run) never exceeds a threshold.
using ResponseFunction = std::function<double(std::uint64_t index, std::span<const double> u)>;

// Chain `chain` of level `level` >= 1 from its seed (u, g), conditional on
// g > threshold.
Chain run_chain(const SubsetSettings& settings, int level, std::uint64_t chain, double threshold,
                std::span<const double> spread, std::span<const double> seed_u, double seed_g,
                const ResponseFunction& response);

// All N states of a level, in index order (level 0: by sample; later: chain
// by chain, state by state).
struct LevelStates {
  std::vector<double> u;               // N x D
  std::vector<double> g;               // N
  std::vector<std::uint8_t> accepted;  // N; level 0: all 0
  std::uint64_t runs = 0;
  std::uint64_t failed_runs = 0;  // later levels: the chains' failed proposals
};

struct LevelSummary {
  double threshold = 0.0;                // b_{j+1}: this level's (1 - p0) quantile, or b at the last
  double conditional_probability = 0.0;  // p_j: the fraction of the level's states beyond it
  double gamma = 0.0;                    // the chains' correlation factor (0 at level 0)
  double acceptance_rate = 0.0;          // accepted proposals / proposals (level 0: 1)
  std::uint64_t runs = 0;
  std::uint64_t failed_runs = 0;  // runs that failed (NaN response): never beyond a threshold
};

// What a level's states give: its summary, whether it is the last, and the
// next level's seeds (positions in the level's states, in the order chains
// take them) and spreads s_i.
// The proposal's spreads s_i = lambda clamp(sigma_i, 0.1, 1): sigma_i the seeds'
// standard deviation in component i, lambda in (0, 1] adapted from level to
// level towards an acceptance rate of 0.44 (never inside a level).
struct Spread {
  double lambda = 0.6;
  std::vector<double> s;
};

struct LevelClose {
  LevelSummary summary;
  bool last = false;
  bool reached_limit = false;        // the threshold reached b (else max_levels ran out)
  bool no_threshold = false;         // N (1 - p0) or more runs failed, or the responses pile up: none exists
  std::vector<std::uint64_t> seeds;  // positions in the level's states
  Spread spread;                     // for the next level's chains
};

// `level` counts from 0; `used` is the spread this level's chains used
// (ignored at level 0). The level is the last when its threshold reaches b
// or when it is level max_levels.
LevelClose close_level(const SubsetSettings& settings, int level, const LevelStates& states, const Spread& used,
                       unsigned dimensions);

struct SubsetResult {
  double probability = 0.0;                        // p0^m N_F / N
  double cov = 0.0;                                // sqrt(sum_j delta_j^2): levels taken as uncorrelated
  double interval_low = 0.0, interval_high = 0.0;  // 95 %: lognormal with that cov
  bool reached_limit = false;                      // false: max_levels ran out before the threshold reached b
  bool no_threshold = false;  // true: a level had no threshold (failed runs, or a pile-up of responses)
  std::uint64_t runs = 0;
  std::vector<LevelSummary> levels;
};

// The estimate and its coefficient of variation from the levels' summaries.
SubsetResult combine(const SubsetSettings& settings, std::vector<LevelSummary> levels, bool reached_limit,
                     bool no_threshold = false);

// What every chain of a level needs, flat for a broadcast: the level, its
// threshold, the spreads, and each chain's seed (response and point).
struct LevelStart {
  int level = 0;
  double threshold = 0.0;
  std::vector<double> spread;  // D
  std::vector<double> seed_g;  // N_c
  std::vector<double> seed_u;  // N_c x D
};
std::vector<double> pack(const LevelStart& start);
LevelStart unpack_level_start(std::span<const double> packed, unsigned dimensions);

// The algorithm one level at a time: level 0, then each later level's
// chains, each level closed as soon as its states are in. A parallel run
// uses it on rank 0 to replay what is finished (with the responses of the
// records so far) and hand out the next level.
class SubsetLevels {
 public:
  SubsetLevels(const SubsetSettings& settings, unsigned dimensions);
  // Level 0's N points and responses; closes it.
  void start(const ResponseFunction& response);
  // The chains of the next level, chain by chain; closes it. Only before finished().
  void advance(const ResponseFunction& response);
  bool finished() const { return close_.last; }
  int level() const { return level_; }  // the last level closed
  const LevelClose& close() const { return close_; }
  // What the chains of level() + 1 start from. Only before finished().
  LevelStart next_start() const;
  SubsetResult result() const;

 private:
  void close_this_level();

  const SubsetSettings settings_;
  unsigned dimensions_;
  int level_ = -1;
  LevelStates states_;
  LevelClose close_;
  Spread spread_;  // the one this level's chains used
  std::vector<LevelSummary> levels_;
};

// The whole algorithm, serially.
SubsetResult subset_simulation(const SubsetSettings& settings, unsigned dimensions, const ResponseFunction& response);

}  // namespace treedyn::designs
