#include "rare_event/subset_simulation.hpp"

#include <boost/math/distributions/normal.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "sampling/design.hpp"

namespace treedyn::rare_event {
namespace {

// Level 0 draws from the Monte-Carlo design's own stream (0), so that it is
// the ordinary Monte-Carlo sample of the same seed; proposals from their own.
constexpr std::uint64_t kLevelZeroStream = 0;
constexpr std::uint64_t kProposalStream = 0x73756273;  // "subs"
constexpr double kTargetAcceptance = 0.44;

double standard_normal(std::uint64_t seed, std::uint64_t index, std::uint64_t input, std::uint64_t stream) {
  return boost::math::quantile(boost::math::normal(), ensemble::counter_uniform(seed, index, input, stream));
}

bool is_whole(double x) { return std::abs(x - std::round(x)) <= 1e-9 * std::max(1.0, std::abs(x)); }

// The level's states from the largest response down, ties by index (a NaN,
// a failed run, counts as the smallest).
std::vector<std::uint64_t> descending(std::span<const double> g) {
  std::vector<std::uint64_t> order(g.size());
  std::iota(order.begin(), order.end(), std::uint64_t{0});
  auto key = [&](std::uint64_t i) { return std::isnan(g[i]) ? -std::numeric_limits<double>::infinity() : g[i]; };
  std::stable_sort(order.begin(), order.end(), [&](std::uint64_t a, std::uint64_t b) { return key(a) > key(b); });
  return order;
}

// gamma_j of the theory page: the chains' indicator sequences I_{c,l}
// = [g_{c,l} > threshold], their autocovariance R(k) over lags k < N_s.
double chain_correlation(const SubsetSettings& settings, std::span<const double> g, double threshold, double p) {
  const std::uint64_t Nc = settings.chains(), Ns = settings.states(), N = settings.samples;
  const double R0 = p - p * p;
  if (!(R0 > 0.0)) return 0.0;
  double gamma = 0.0;
  for (std::uint64_t k = 1; k < Ns; ++k) {
    std::uint64_t both = 0;
    for (std::uint64_t c = 0; c < Nc; ++c)
      for (std::uint64_t l = 0; l + k < Ns; ++l)
        both += (g[c * Ns + l] > threshold && g[c * Ns + l + k] > threshold) ? 1 : 0;
    const double R = static_cast<double>(both) / static_cast<double>(N - k * Nc) - p * p;
    gamma += 2.0 * (1.0 - static_cast<double>(k) / static_cast<double>(Ns)) * R / R0;
  }
  return gamma;
}

// s_i = lambda min(1, sigma_i), sigma_i the seeds' sample standard
// deviation: a component the failure domain narrows gets a narrower step,
// and none a wider one than the prior's. (Papaioannou et al. take
// min(1, lambda sigma_i) and adapt lambda inside a level; here lambda
// changes only between levels, and on a failure domain that surrounds the
// origin the seeds' sigma_i exceed 1 and a step of 1 is an independent
// proposal that is almost never accepted at deep levels.)
Spread next_spread(const LevelStates& states, std::span<const std::uint64_t> seeds, unsigned D, double lambda) {
  Spread next{lambda, std::vector<double>(D, 1.0)};
  const double n = static_cast<double>(seeds.size());
  if (seeds.size() < 2) {
    std::fill(next.s.begin(), next.s.end(), lambda);
    return next;
  }
  for (unsigned i = 0; i < D; ++i) {
    double mean = 0.0, square = 0.0;
    for (std::uint64_t k : seeds) mean += states.u[k * D + i] / n;
    for (std::uint64_t k : seeds) square += (states.u[k * D + i] - mean) * (states.u[k * D + i] - mean);
    next.s[i] = lambda * std::min(1.0, std::sqrt(square / (n - 1.0)));
  }
  return next;
}

}  // namespace

std::uint64_t SubsetSettings::chains() const { return samples / states(); }
std::uint64_t SubsetSettings::states() const { return static_cast<std::uint64_t>(std::llround(1.0 / level_probability)); }

std::string check(const SubsetSettings& s) {
  if (!(s.level_probability > 0.0 && s.level_probability <= 0.5))
    return "level_probability must be in (0, 0.5]; 0.1 is the usual value";
  if (!is_whole(1.0 / s.level_probability))
    return "1 / level_probability must be a whole number (0.1, 0.2, 0.25, 0.5, ...)";
  if (s.samples < 2 || s.samples % s.states() != 0)
    return "samples (per level) times level_probability must be a whole number of at least 1 (samples = " +
           std::to_string(s.samples) + ", 1 / level_probability = " + std::to_string(s.states()) + ")";
  if (s.max_levels < 1 || s.max_levels > 100) return "max_levels must be between 1 and 100";
  if (!std::isfinite(s.limit)) return "the response's limit must be finite";
  return {};
}

std::uint64_t run_index(const SubsetSettings& s, const RunPlace& p) {
  if (p.level == 0) return p.chain;
  return static_cast<std::uint64_t>(p.level) * s.samples + p.chain * s.states() + p.state;
}

RunPlace run_place(const SubsetSettings& s, std::uint64_t index) {
  const auto level = static_cast<int>(index / s.samples);
  const std::uint64_t within = index % s.samples;
  if (level == 0) return {0, within, 0};
  return {level, within / s.states(), within % s.states()};
}

void level_zero_point(const SubsetSettings& s, std::uint64_t k, std::span<double> u) {
  for (std::size_t i = 0; i < u.size(); ++i) u[i] = standard_normal(s.seed, k, i, kLevelZeroStream);
}

void propose(const SubsetSettings& s, std::uint64_t index, std::span<const double> spread, std::span<const double> u,
             std::span<double> v) {
  for (std::size_t i = 0; i < u.size(); ++i) {
    const double rho = std::sqrt(1.0 - spread[i] * spread[i]);
    v[i] = rho * u[i] + spread[i] * standard_normal(s.seed, index, i, kProposalStream);
  }
}

Chain run_chain(const SubsetSettings& s, int level, std::uint64_t chain_index, double threshold,
                std::span<const double> spread, std::span<const double> seed_u, double seed_g,
                const Response& response) {
  const std::uint64_t Ns = s.states();
  const std::size_t D = seed_u.size();
  Chain chain;
  chain.u.resize(Ns * D);
  chain.g.resize(Ns);
  chain.accepted.assign(Ns, 0);
  std::copy(seed_u.begin(), seed_u.end(), chain.u.begin());
  chain.g[0] = seed_g;
  std::vector<double> v(D);
  for (std::uint64_t l = 1; l < Ns; ++l) {
    const std::uint64_t index = run_index(s, {level, chain_index, l});
    const std::span<const double> current(chain.u.data() + (l - 1) * D, D);
    propose(s, index, spread, current, v);
    const double g = response(index, v);
    ++chain.runs;
    const bool accept = g > threshold;  // false for NaN
    const std::span<const double> next = accept ? std::span<const double>(v) : current;
    std::copy(next.begin(), next.end(), chain.u.begin() + static_cast<std::ptrdiff_t>(l * D));
    chain.g[l] = accept ? g : chain.g[l - 1];
    chain.accepted[l] = accept ? 1 : 0;
  }
  return chain;
}

LevelClose close_level(const SubsetSettings& s, int level, const LevelStates& states, const Spread& used,
                       unsigned D) {
  const std::uint64_t N = s.samples, Nc = s.chains();
  const std::vector<std::uint64_t> order = descending(states.g);
  const double next = 0.5 * (states.g[order[Nc - 1]] + states.g[order[Nc]]);
  LevelClose close;
  close.reached_limit = next >= s.limit;
  close.last = close.reached_limit || level >= s.max_levels;
  LevelSummary& summary = close.summary;
  summary.threshold = close.last ? s.limit : next;
  // An intermediate level's probability is p0 by construction: its N p0
  // largest states (ties broken by index) seed the next level, whether or
  // not a repeated state sits exactly on the threshold. The last level
  // counts its states beyond b (N_F / N).
  const auto beyond = std::count_if(states.g.begin(), states.g.end(), [&](double g) { return g > summary.threshold; });
  summary.conditional_probability =
      close.last ? static_cast<double>(beyond) / static_cast<double>(N) : s.level_probability;
  summary.gamma = level == 0 ? 0.0 : chain_correlation(s, states.g, summary.threshold, summary.conditional_probability);
  const auto accepted = std::count(states.accepted.begin(), states.accepted.end(), std::uint8_t{1});
  summary.acceptance_rate =
      level == 0 ? 1.0 : static_cast<double>(accepted) / static_cast<double>(std::max<std::uint64_t>(states.runs, 1));
  summary.runs = states.runs;
  if (close.last) return close;
  close.seeds.assign(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(Nc));
  const double lambda =
      level == 0 ? used.lambda
                 : std::clamp(used.lambda * std::exp(summary.acceptance_rate - kTargetAcceptance), 0.05, 1.0);
  close.spread = next_spread(states, close.seeds, D, lambda);
  return close;
}

SubsetResult combine(const SubsetSettings& s, std::vector<LevelSummary> levels, bool reached_limit) {
  SubsetResult r;
  r.reached_limit = reached_limit;
  r.probability = 1.0;
  double variance = 0.0;  // sum of delta_j^2
  const double N = static_cast<double>(s.samples);
  for (const LevelSummary& level : levels) {
    const double p = level.conditional_probability;
    r.probability *= p;
    variance += p > 0.0 ? (1.0 - p) / (N * p) * (1.0 + level.gamma) : std::numeric_limits<double>::infinity();
    r.runs += level.runs;
  }
  r.cov = std::sqrt(variance);
  if (r.probability > 0.0) {
    // 95 %: the estimate taken as lognormal with this coefficient of variation.
    const double sigma = std::sqrt(std::log1p(variance));
    r.interval_low = r.probability * std::exp(-1.96 * sigma);
    r.interval_high = r.probability * std::exp(1.96 * sigma);
  } else {
    // No exceedance at the last level: the rule of three there (3 / N),
    // times the levels before.
    r.interval_high = 3.0 / N;
    for (std::size_t j = 0; j + 1 < levels.size(); ++j) r.interval_high *= levels[j].conditional_probability;
  }
  r.levels = std::move(levels);
  return r;
}

SubsetResult subset_simulation(const SubsetSettings& s, unsigned D, const Response& response) {
  if (const std::string problem = check(s); !problem.empty()) throw std::invalid_argument(problem);
  const std::uint64_t N = s.samples;
  LevelStates states;
  states.u.resize(N * D);
  states.g.resize(N);
  states.accepted.assign(N, 0);
  for (std::uint64_t k = 0; k < N; ++k) {
    const std::span<double> u(states.u.data() + k * D, D);
    level_zero_point(s, k, u);
    states.g[k] = response(k, u);
  }
  states.runs = N;
  std::vector<LevelSummary> levels;
  Spread spread;
  for (int level = 0;; ++level) {
    LevelClose close = close_level(s, level, states, spread, D);
    levels.push_back(close.summary);
    if (close.last) return combine(s, std::move(levels), close.reached_limit);
    LevelStates next;
    for (std::uint64_t c = 0; c < s.chains(); ++c) {
      const std::uint64_t seed = close.seeds[c];
      const Chain chain = run_chain(s, level + 1, c, close.summary.threshold, close.spread.s,
                                    std::span<const double>(states.u.data() + seed * D, D), states.g[seed], response);
      next.u.insert(next.u.end(), chain.u.begin(), chain.u.end());
      next.g.insert(next.g.end(), chain.g.begin(), chain.g.end());
      next.accepted.insert(next.accepted.end(), chain.accepted.begin(), chain.accepted.end());
      next.runs += chain.runs;
    }
    states = std::move(next);
    spread = std::move(close.spread);
  }
}

}  // namespace treedyn::rare_event
