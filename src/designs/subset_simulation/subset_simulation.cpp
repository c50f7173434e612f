#include "designs/subset_simulation/subset_simulation.hpp"

#include <boost/math/distributions/normal.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "sampling/design.hpp"

namespace treedyn::designs {
namespace {

// Level 0 draws from the Monte-Carlo design's own stream (0), so that it is
// the ordinary Monte-Carlo sample of the same seed; proposals from their own.
constexpr std::uint64_t kLevelZeroStream = 0;
constexpr std::uint64_t kProposalStream = 0x73756273;  // "subs"
constexpr double kTargetAcceptance = 0.44;

double standard_normal(std::uint64_t seed, std::uint64_t index, std::uint64_t input, std::uint64_t stream) {
  return boost::math::quantile(boost::math::normal(), sampling::counter_uniform(seed, index, input, stream));
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

// gamma_j of docs/rare_events.md, section 3: the chains' indicator sequences I_{c,l}
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
    // At least 0.1: seeds that are copies of one state must not freeze a component.
    next.s[i] = lambda * std::clamp(std::sqrt(square / (n - 1.0)), 0.1, 1.0);
  }
  return next;
}

}  // namespace

std::uint64_t SubsetSettings::chains() const { return samples / states(); }
std::uint64_t SubsetSettings::states() const {
  return static_cast<std::uint64_t>(std::llround(1.0 / level_probability));
}

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

namespace {
std::uint64_t runs_per_chain_level(const SubsetSettings& s) { return s.chains() * (s.states() - 1); }
}  // namespace

std::uint64_t runs_before(const SubsetSettings& s, int levels) {
  if (levels <= 0) return 0;
  return s.samples + static_cast<std::uint64_t>(levels - 1) * runs_per_chain_level(s);
}

std::uint64_t run_index(const SubsetSettings& s, const RunPlace& p) {
  if (p.level == 0) return p.chain;
  return runs_before(s, p.level) + p.chain * (s.states() - 1) + p.state - 1;
}

RunPlace run_place(const SubsetSettings& s, std::uint64_t index) {
  if (index < s.samples) return {0, index, 0};
  const std::uint64_t r = index - s.samples, R = runs_per_chain_level(s);
  const std::uint64_t within = r % R;
  return {1 + static_cast<int>(r / R), within / (s.states() - 1), 1 + within % (s.states() - 1)};
}

double to_uniform(double u) {
  const double v = boost::math::cdf(boost::math::normal(), u);
  return std::clamp(v, std::numeric_limits<double>::min(), std::nextafter(1.0, 0.0));
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
                const ResponseFunction& response) {
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
    chain.failed_runs += std::isnan(g) ? 1 : 0;
    const bool accept = g > threshold;  // false for NaN
    const std::span<const double> next = accept ? std::span<const double>(v) : current;
    std::copy(next.begin(), next.end(), chain.u.begin() + static_cast<std::ptrdiff_t>(l * D));
    chain.g[l] = accept ? g : chain.g[l - 1];
    chain.accepted[l] = accept ? 1 : 0;
  }
  return chain;
}

namespace {

// Whether the states tied with the N p0-th largest are more than one
// chain's repeats of one state. A rejected proposal repeats a state, so such
// ties are ordinary: the index order breaks them and the level's probability
// is p0. A tie at level 0, across chains or at +-inf is a pile-up of the
// response at one value (a level never crossed is +inf, say): then only the
// count beyond it is a probability.
bool piled_up(const SubsetSettings& s, int level, std::span<const double> g, std::span<const std::uint64_t> order) {
  const double boundary = g[order[s.chains() - 1]];
  if (!(g[order[s.chains()]] == boundary)) return false;
  if (level == 0 || std::isinf(boundary)) return true;
  std::uint64_t chain = s.samples;  // none yet
  for (std::uint64_t k = 0; k < g.size(); ++k) {
    if (!(g[k] == boundary)) continue;
    if (chain != s.samples && k / s.states() != chain) return true;
    chain = k / s.states();
  }
  return false;
}

// The next level's seeds: the N p0 largest states; after a pile-up, the
// states beyond it, taken in turn until there are N p0.
std::vector<std::uint64_t> seeds_of(const SubsetSettings& s, std::span<const double> g,
                                    std::span<const std::uint64_t> order, bool piled, double threshold) {
  std::vector<std::uint64_t> seeds(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(s.chains()));
  if (!piled) return seeds;
  std::uint64_t beyond = 0;
  while (beyond < order.size() && g[order[beyond]] > threshold) ++beyond;
  for (std::uint64_t c = 0; c < seeds.size(); ++c) seeds[c] = order[c % beyond];
  return seeds;
}

}  // namespace

LevelClose close_level(const SubsetSettings& s, int level, const LevelStates& states, const Spread& used, unsigned D) {
  const std::uint64_t N = s.samples, Nc = s.chains();
  const std::vector<std::uint64_t> order = descending(states.g);
  const bool piled = piled_up(s, level, states.g, order);
  const double next = piled ? states.g[order[Nc - 1]] : 0.5 * (states.g[order[Nc - 1]] + states.g[order[Nc]]);
  const auto count_beyond = [&](double b) {
    return static_cast<std::uint64_t>(std::count_if(states.g.begin(), states.g.end(), [&](double g) { return g > b; }));
  };
  LevelClose close;
  close.reached_limit = next >= s.limit;
  // No threshold: N (1 - p0) or more runs failed (NaN sorts last), or the
  // responses pile up at the level's largest value; the simulation ends here.
  close.no_threshold = std::isnan(next) || (piled && count_beyond(next) == 0);
  close.last = close.reached_limit || close.no_threshold || level >= s.max_levels;
  LevelSummary& summary = close.summary;
  summary.failed_runs = level == 0 ? static_cast<std::uint64_t>(std::count_if(states.g.begin(), states.g.end(),
                                                                              [](double g) { return std::isnan(g); }))
                                   : states.failed_runs;
  summary.threshold = close.last ? s.limit : next;
  // An intermediate level's probability is p0 by construction (its N p0
  // largest states, ties broken by index, seed the next level), but after a
  // pile-up it is the count beyond; the last level counts N_F / N.
  summary.conditional_probability = close.last || piled
                                        ? static_cast<double>(count_beyond(summary.threshold)) / static_cast<double>(N)
                                        : s.level_probability;
  summary.gamma = level == 0 ? 0.0 : chain_correlation(s, states.g, summary.threshold, summary.conditional_probability);
  const auto accepted = std::count(states.accepted.begin(), states.accepted.end(), std::uint8_t{1});
  summary.acceptance_rate =
      level == 0 ? 1.0 : static_cast<double>(accepted) / static_cast<double>(std::max<std::uint64_t>(states.runs, 1));
  summary.runs = states.runs;
  if (close.last) return close;
  close.seeds = seeds_of(s, states.g, order, piled, next);
  const double lambda =
      level == 0 ? used.lambda
                 : std::clamp(used.lambda * std::exp(summary.acceptance_rate - kTargetAcceptance), 0.05, 1.0);
  close.spread = next_spread(states, close.seeds, D, lambda);
  return close;
}

SubsetResult combine(const SubsetSettings& s, std::vector<LevelSummary> levels, bool reached_limit, bool no_threshold) {
  SubsetResult r;
  r.reached_limit = reached_limit;
  r.no_threshold = no_threshold;
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

std::vector<double> pack(const LevelStart& start) {
  std::vector<double> out{static_cast<double>(start.level), start.threshold};
  out.insert(out.end(), start.spread.begin(), start.spread.end());
  out.insert(out.end(), start.seed_g.begin(), start.seed_g.end());
  out.insert(out.end(), start.seed_u.begin(), start.seed_u.end());
  return out;
}

LevelStart unpack_level_start(std::span<const double> packed, unsigned D) {
  if (packed.size() < 2 + D || (packed.size() - 2 - D) % (D + 1) != 0)
    throw std::invalid_argument("a level's start of the wrong size");
  LevelStart start;
  start.level = static_cast<int>(packed[0]);
  start.threshold = packed[1];
  const std::size_t chains = (packed.size() - 2 - D) / (D + 1);
  auto at = packed.begin() + 2;
  start.spread.assign(at, at + D);
  start.seed_g.assign(at + D, at + static_cast<std::ptrdiff_t>(D + chains));
  start.seed_u.assign(at + static_cast<std::ptrdiff_t>(D + chains), packed.end());
  return start;
}

SubsetLevels::SubsetLevels(const SubsetSettings& s, unsigned D) : settings_(s), dimensions_(D) {
  if (const std::string problem = check(s); !problem.empty()) throw std::invalid_argument(problem);
}

void SubsetLevels::start(const ResponseFunction& response) {
  const std::uint64_t N = settings_.samples;
  const unsigned D = dimensions_;
  states_ = LevelStates{};
  states_.u.resize(N * D);
  states_.g.resize(N);
  states_.accepted.assign(N, 0);
  for (std::uint64_t k = 0; k < N; ++k) {
    const std::span<double> u(states_.u.data() + k * D, D);
    level_zero_point(settings_, k, u);
    states_.g[k] = response(k, u);
  }
  states_.runs = N;
  level_ = 0;
  close_this_level();
}

LevelStart SubsetLevels::next_start() const {
  const unsigned D = dimensions_;
  LevelStart start{level_ + 1, close_.summary.threshold, close_.spread.s, {}, {}};
  for (std::uint64_t seed : close_.seeds) {
    start.seed_g.push_back(states_.g[seed]);
    start.seed_u.insert(start.seed_u.end(), states_.u.begin() + static_cast<std::ptrdiff_t>(seed * D),
                        states_.u.begin() + static_cast<std::ptrdiff_t>((seed + 1) * D));
  }
  return start;
}

void SubsetLevels::advance(const ResponseFunction& response) {
  if (finished()) throw std::logic_error("subset simulation: no level after the last");
  const unsigned D = dimensions_;
  const LevelStart start = next_start();
  LevelStates next;
  for (std::uint64_t c = 0; c < start.seed_g.size(); ++c) {
    const Chain chain = run_chain(settings_, start.level, c, start.threshold, start.spread,
                                  std::span<const double>(start.seed_u.data() + c * D, D), start.seed_g[c], response);
    next.u.insert(next.u.end(), chain.u.begin(), chain.u.end());
    next.g.insert(next.g.end(), chain.g.begin(), chain.g.end());
    next.accepted.insert(next.accepted.end(), chain.accepted.begin(), chain.accepted.end());
    next.runs += chain.runs;
    next.failed_runs += chain.failed_runs;
  }
  spread_ = close_.spread;
  states_ = std::move(next);
  level_ = start.level;
  close_this_level();
}

void SubsetLevels::close_this_level() {
  close_ = close_level(settings_, level_, states_, spread_, dimensions_);
  levels_.push_back(close_.summary);
}

SubsetResult SubsetLevels::result() const {
  return combine(settings_, levels_, close_.reached_limit, close_.no_threshold);
}

SubsetResult subset_simulation(const SubsetSettings& s, unsigned D, const ResponseFunction& response) {
  SubsetLevels levels(s, D);
  levels.start(response);
  while (!levels.finished()) levels.advance(response);
  return levels.result();
}

}  // namespace treedyn::designs
