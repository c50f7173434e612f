// Sensitivity measures (src/analysis/sensitivity.*) on hand examples and
// known functions:
//
//  * AverageRanks*, Spearman*: small hand examples with exact answers.
//  * Srrc*: a linear response of independent uniform inputs, and the cases
//    the header declares NaN.
//  * Ishigami*: Sobol' indices from the project's Saltelli design against
//    the analytic values; the bootstrap's reproducibility and its
//    percentile recipe; a constant response.
#include "analysis/sensitivity.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <iostream>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "designs/saltelli/sobol_indices.hpp"
#include "designs/sample_design.hpp"
#include "sampling/design.hpp"

namespace {

using namespace treedyn;
using namespace treedyn::analysis;
using namespace treedyn::sampling;
using treedyn::designs::saltelli_indices;
using treedyn::designs::SampleDesign;
using treedyn::designs::SobolIndices;

constexpr double kInf = std::numeric_limits<double>::infinity();

// ---------------------------------------------------------------------------
// Ranks and Spearman's correlation.

// Ranks of small integers and their means (x.5) are exact in double: the
// comparison is exact.
TEST(AverageRanks, TiesShareTheirMeanRank) {
  const std::vector<double> values{3, 1, 4, 1, 5};
  EXPECT_EQ(average_ranks(values), (std::vector<double>{3, 1.5, 4, 1.5, 5}));

  const std::vector<double> triple{2, 2, 2, 0};
  EXPECT_EQ(average_ranks(triple), (std::vector<double>{3, 3, 3, 1}));

  EXPECT_TRUE(average_ranks(std::vector<double>{}).empty());
}

// Exact, as above: +-inf are ordinary extremes and equal infinities tie.
TEST(AverageRanks, InfinitiesRankAsExtremes) {
  const std::vector<double> values{kInf, -kInf, 0.0, kInf, -1.0};
  EXPECT_EQ(average_ranks(values), (std::vector<double>{4.5, 1, 3, 4.5, 2}));
}

TEST(AverageRanks, RefusesNaN) {
  const std::vector<double> values{1.0, std::numeric_limits<double>::quiet_NaN()};
  EXPECT_THROW(average_ranks(values), std::invalid_argument);
}

// Identical (or exactly negated) centred rank vectors: the correlation is
// +-1 up to the rounding of one division and one square root, so 1e-14.
TEST(Spearman, MonotoneTransformsGivePlusOrMinusOne) {
  const std::size_t n = 50;
  std::vector<double> x(n), increasing(n), decreasing(n);
  for (std::size_t k = 0; k < n; ++k) {
    x[k] = counter_uniform(11, k, 0, 0) * 4.0 - 2.0;
    increasing[k] = std::exp(3.0 * x[k]) + x[k];  // strictly increasing, far from linear
    decreasing[k] = -x[k] * x[k] * x[k];          // strictly decreasing
  }
  const RankSensitivity up = rank_sensitivity(x, 1, increasing);
  const RankSensitivity down = rank_sensitivity(x, 1, decreasing);
  EXPECT_NEAR(up.spearman[0], 1.0, 1e-14);
  EXPECT_NEAR(down.spearman[0], -1.0, 1e-14);
  EXPECT_EQ(up.samples, n);
}

// Without ties, rho = 1 - 6 sum d^2 / (n (n^2 - 1)) exactly; the rank
// differences are listed by hand. Both sides are rounded only a few times:
// 1e-14.
TEST(Spearman, MatchesTheClosedFormWithoutTies) {
  const std::vector<double> x{0.3, 1.7, -2.0, 4.1, 0.9, 2.5};  // ranks 2 4 1 6 3 5
  const std::vector<double> y{10, 30, 5, 20, 60, 40};          // ranks 2 4 1 3 6 5
  const double d[] = {0, 0, 0, 3, -3, 0};
  double sum_d2 = 0.0;
  for (const double v : d) sum_d2 += v * v;
  const double n = 6.0;
  const double expected = 1.0 - 6.0 * sum_d2 / (n * (n * n - 1.0));  // 17/35
  EXPECT_NEAR(expected, 17.0 / 35.0, 1e-15);
  EXPECT_NEAR(rank_sensitivity(x, 1, y).spearman[0], expected, 1e-14);
}

// ---------------------------------------------------------------------------
// Standardised rank regression coefficients.

// y = 2 x1 - x2 + 0 x3 with n = 2000 independent U(0, 1) inputs. Deterministic
// (counter-based inputs), but the bounds are set by the sampling error: with
// R^2 ~ 0.99 the standard error of a coefficient is about
// sqrt((1 - R^2) / (n - d - 1)) ~ 0.002, so |SRRC_3| < 0.02 is 9 of them;
// the rank transform of a linear function of uniforms is close to linear,
// hence R^2 > 0.9 (measured: 0.990).
TEST(Srrc, LinearResponseOfIndependentInputs) {
  const std::size_t n = 2000, d = 3;
  std::vector<double> inputs(n * d), response(n);
  for (std::size_t k = 0; k < n; ++k) {
    for (std::size_t i = 0; i < d; ++i) inputs[k * d + i] = counter_uniform(2024, k, i, 0);
    response[k] = 2.0 * inputs[k * d] - inputs[k * d + 1] + 0.0 * inputs[k * d + 2];
  }
  const RankSensitivity s = rank_sensitivity(inputs, d, response);
  std::cout << "SRRC " << s.srrc[0] << " " << s.srrc[1] << " " << s.srrc[2] << ", R^2 " << s.r_squared << ", Spearman "
            << s.spearman[0] << " " << s.spearman[1] << " " << s.spearman[2] << "\n";
  ASSERT_EQ(s.samples, n);
  EXPECT_GT(s.r_squared, 0.9);
  EXPECT_LE(s.r_squared, 1.0);
  EXPECT_GT(s.srrc[0], 0.0);
  EXPECT_LT(s.srrc[1], 0.0);
  EXPECT_GT(std::abs(s.srrc[0]), std::abs(s.srrc[1]));  // x1 matters twice as much
  EXPECT_GT(std::abs(s.srrc[1]), 0.2);                  // and x2 clearly matters
  EXPECT_LT(std::abs(s.srrc[2]), 0.02);
  EXPECT_LT(std::abs(s.spearman[2]), 0.1);  // 1/sqrt(n) ~ 0.022 is its null spread
}

// The NaN rules are structural, so exact (NaN or not) checks.
TEST(Srrc, NaNWithTooFewRowsOrASingularRegression) {
  const std::size_t d = 3;
  // n = d + 1 = 4 rows: no residual degree of freedom, SRRC NaN; the
  // correlations remain defined.
  const std::vector<double> four_rows{0.1, 0.7, 0.3,  //
                                      0.5, 0.2, 0.9,  //
                                      0.8, 0.4, 0.1,  //
                                      0.3, 0.9, 0.6};
  const std::vector<double> four_responses{1.0, 3.0, 2.0, 4.0};
  const RankSensitivity few = rank_sensitivity(four_rows, d, four_responses);
  for (std::size_t i = 0; i < d; ++i) {
    EXPECT_TRUE(std::isnan(few.srrc[i])) << i;
    EXPECT_FALSE(std::isnan(few.spearman[i])) << i;
  }
  EXPECT_TRUE(std::isnan(few.r_squared));

  // n = 30 with input 1 constant: its Spearman is NaN, and the regression is
  // singular, so every SRRC is NaN; the other correlations are defined.
  const std::size_t n = 30;
  std::vector<double> inputs(n * d), response(n);
  for (std::size_t k = 0; k < n; ++k) {
    inputs[k * d] = counter_uniform(5, k, 0, 0);
    inputs[k * d + 1] = 0.25;
    inputs[k * d + 2] = counter_uniform(5, k, 2, 0);
    response[k] = inputs[k * d] + inputs[k * d + 2] * inputs[k * d + 2];
  }
  const RankSensitivity constant = rank_sensitivity(inputs, d, response);
  EXPECT_TRUE(std::isnan(constant.spearman[1]));
  EXPECT_FALSE(std::isnan(constant.spearman[0]));
  EXPECT_FALSE(std::isnan(constant.spearman[2]));
  for (std::size_t i = 0; i < d; ++i) EXPECT_TRUE(std::isnan(constant.srrc[i])) << i;

  // Input 1 a monotone function of input 0: identical ranks, collinear.
  for (std::size_t k = 0; k < n; ++k) inputs[k * d + 1] = std::exp(inputs[k * d]);
  const RankSensitivity collinear = rank_sensitivity(inputs, d, response);
  for (std::size_t i = 0; i < d; ++i) EXPECT_TRUE(std::isnan(collinear.srrc[i])) << i;
  EXPECT_TRUE(std::isnan(collinear.r_squared));

  // A constant response: no correlations at all.
  const std::vector<double> flat(n, 1.0);
  const RankSensitivity none = rank_sensitivity(inputs, d, flat);
  for (std::size_t i = 0; i < d; ++i) {
    EXPECT_TRUE(std::isnan(none.spearman[i])) << i;
    EXPECT_TRUE(std::isnan(none.srrc[i])) << i;
  }
}

// ---------------------------------------------------------------------------
// Sobol' indices on the Ishigami function.

constexpr double kA = 7.0, kB = 0.1;
constexpr unsigned kInputs = 3;
constexpr std::size_t kBase = std::size_t{1} << 14;  // N
constexpr int kResamples = 200;
constexpr std::uint64_t kDesignSeed = 20240611;

double ishigami(const double* x) {
  return std::sin(x[0]) + kA * std::sin(x[1]) * std::sin(x[1]) + kB * std::pow(x[2], 4) * std::sin(x[0]);
}

// f(A), f(B), f(AB_g) on N base points of the project's Saltelli design,
// inputs mapped from (0, 1) to (-pi, pi); `unit_of_input` groups inputs
// (empty: each input alone).
struct SaltelliRuns {
  std::vector<double> f_a, f_b, f_ab;
};

SaltelliRuns ishigami_runs(std::size_t base, std::uint64_t seed, std::vector<unsigned> unit_of_input = {}) {
  const unsigned units =
      unit_of_input.empty() ? kInputs : *std::max_element(unit_of_input.begin(), unit_of_input.end()) + 1;
  const std::uint64_t block = saltelli_block(units);
  const SampleDesign design(Design::saltelli, seed, base * block, kInputs, unit_of_input);
  SaltelliRuns runs;
  runs.f_a.resize(base);
  runs.f_b.resize(base);
  runs.f_ab.resize(base * units);
  double u[kInputs], x[kInputs];
  for (std::uint64_t k = 0; k < base * block; ++k) {
    design.point(k, u);
    for (unsigned i = 0; i < kInputs; ++i) x[i] = std::numbers::pi * (2.0 * u[i] - 1.0);
    const double f = ishigami(x);
    const SaltelliPlace at = saltelli_place(k, units);
    // clang-format off
    switch (at.role) {
      case SaltelliRole::a: runs.f_a[at.base] = f; break;
      case SaltelliRole::b: runs.f_b[at.base] = f; break;
      case SaltelliRole::ab: runs.f_ab[at.base * units + at.unit] = f; break;
    }
    // clang-format on
  }
  return runs;
}

const SaltelliRuns& runs() {
  static const SaltelliRuns computed = ishigami_runs(kBase, kDesignSeed);
  return computed;
}

// Analytic indices (e.g. Saltelli et al., Global Sensitivity Analysis: The
// Primer, 2008, section 4.9): V = a^2/8 + b pi^4/5 + b^2 pi^8/18 + 1/2,
// V1 = (1 + b pi^4/5)^2 / 2, V2 = a^2/8, V3 = 0, V13 = b^2 pi^8 (1/18 - 1/50).
struct Analytic {
  double variance;
  double first[kInputs], total[kInputs];
};

Analytic ishigami_indices() {
  const double pi4 = std::pow(std::numbers::pi, 4), pi8 = pi4 * pi4;
  const double v = kA * kA / 8.0 + kB * pi4 / 5.0 + kB * kB * pi8 / 18.0 + 0.5;
  const double v1 = 0.5 * (1.0 + kB * pi4 / 5.0) * (1.0 + kB * pi4 / 5.0);
  const double v2 = kA * kA / 8.0;
  const double v13 = kB * kB * pi8 * (1.0 / 18.0 - 1.0 / 50.0);
  return {v, {v1 / v, v2 / v, 0.0}, {(v1 + v13) / v, v2 / v, v13 / v}};
}

std::string describe(const SobolIndices& s) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(4) << "V " << s.variance << ", N " << s.base_samples;
  for (std::size_t i = 0; i < s.first.size(); ++i)
    out << "\n  x" << i + 1 << ": S " << s.first[i] << " [" << s.first_ci[2 * i] << ", " << s.first_ci[2 * i + 1]
        << "]  ST " << s.total[i] << " [" << s.total_ci[2 * i] << ", " << s.total_ci[2 * i + 1] << "]";
  return out.str();
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// The analytic values rounded to 4 digits, as quoted in the literature; the
// computed ones must round to them (5e-5 plus a rounding margin).
TEST(Ishigami, AnalyticValuesAreTheQuotedOnes) {
  const Analytic exact = ishigami_indices();
  const double s[] = {0.3139, 0.4424, 0.0}, st[] = {0.5576, 0.4424, 0.2437};
  for (unsigned i = 0; i < kInputs; ++i) {
    EXPECT_NEAR(exact.first[i], s[i], 6e-5) << i;
    EXPECT_NEAR(exact.total[i], st[i], 6e-5) << i;
  }
}

// N = 2^14 Owen-scrambled Sobol base points. The estimators' Monte-Carlo
// standard errors at this N are about 0.005-0.01 (the bootstrap half-widths
// printed below are ~2 of them); scrambled QMC does better still (over
// design seeds 1..20 the worst error was 0.0019). 0.02 absolute is
// therefore a few standard errors even for plain Monte Carlo, tight enough
// to catch a wrong formula (a swapped A/B or a missing factor 1/2 moves an
// index by 0.1 or more). The bootstrap treats the blocks as
// i.i.d., so its interval is, if anything, too wide for QMC: the analytic
// value must lie inside it, within a margin of 0.005 for rounding of the
// percentile at the interval's edge.
TEST(Ishigami, IndicesMatchTheAnalyticValues) {
  const SaltelliRuns& r = runs();
  const SobolIndices s = saltelli_indices(r.f_a, r.f_b, r.f_ab, kInputs, kResamples, 1);
  const Analytic exact = ishigami_indices();
  std::cout << "Ishigami (a = 7, b = 0.1), analytic V " << exact.variance << "\n" << describe(s) << "\n";
  RecordProperty("ishigami", describe(s));

  ASSERT_EQ(s.base_samples, kBase);
  ASSERT_EQ(s.first.size(), kInputs);
  ASSERT_EQ(s.first_ci.size(), 2 * kInputs);
  ASSERT_EQ(s.total_ci.size(), 2 * kInputs);
  // V over 2N values: relative error ~ sqrt(kurtosis / 2N) ~ 1 %: 3 %.
  EXPECT_NEAR(s.variance, exact.variance, 0.03 * exact.variance);
  const double tolerance = 0.02, margin = 0.005;
  for (unsigned i = 0; i < kInputs; ++i) {
    EXPECT_NEAR(s.first[i], exact.first[i], tolerance) << "S_" << i + 1;
    EXPECT_NEAR(s.total[i], exact.total[i], tolerance) << "ST_" << i + 1;
    EXPECT_LT(s.first_ci[2 * i], s.first_ci[2 * i + 1]) << i;
    EXPECT_LT(s.total_ci[2 * i], s.total_ci[2 * i + 1]) << i;
    EXPECT_GE(exact.first[i], s.first_ci[2 * i] - margin) << "S_" << i + 1;
    EXPECT_LE(exact.first[i], s.first_ci[2 * i + 1] + margin) << "S_" << i + 1;
    EXPECT_GE(exact.total[i], s.total_ci[2 * i] - margin) << "ST_" << i + 1;
    EXPECT_LE(exact.total[i], s.total_ci[2 * i + 1] + margin) << "ST_" << i + 1;
  }
}

// Grouped indices ([[ensemble.group]]): x1 and x3 moved together in one AB
// block (N (G + 2) = 4N runs). With no interaction between the group and
// x2, the group's first-order and total indices are both 1 - V2/V = 0.5576
// and x2's both V2/V = 0.4424 (the group holds V1 + V3 + V13). Tolerance
// 0.01: the ungrouped estimates at this N are within 0.002 of the analytic
// values (see above), the group's estimator is the same one on a coarser
// split; 0.01 still catches a group taking one input from B instead of two
// (its first-order index would fall to S1 = 0.31).
TEST(Ishigami, GroupedIndicesOfX1AndX3TogetherMatchTheAnalyticValues) {
  const SaltelliRuns r = ishigami_runs(kBase, kDesignSeed, {0, 1, 0});
  const SobolIndices s = saltelli_indices(r.f_a, r.f_b, r.f_ab, 2, kResamples, 1);
  const Analytic exact = ishigami_indices();
  const double x2 = exact.first[1], group = 1.0 - x2;
  std::cout << "Ishigami, groups {x1, x3} and {x2}:\n" << describe(s) << "\n";
  ASSERT_EQ(s.first.size(), 2u);
  EXPECT_NEAR(group, 0.5576, 6e-5);
  EXPECT_NEAR(s.first[0], group, 0.01);
  EXPECT_NEAR(s.total[0], group, 0.01);
  EXPECT_NEAR(s.first[1], x2, 0.01);
  EXPECT_NEAR(s.total[1], x2, 0.01);
  // The A and B runs are the ungrouped design's, bit for bit: a group
  // changes only which inputs an AB run takes from B.
  EXPECT_TRUE(same_bits(r.f_a, runs().f_a));
  EXPECT_TRUE(same_bits(r.f_b, runs().f_b));
}

// Reproducibility is bitwise: the same inputs and seed give the same bits.
// A different bootstrap seed draws other resamples (intervals differ), but
// the point estimates do not use the seed (bitwise equal).
TEST(Ishigami, BootstrapIsReproducibleAndSeedOnlyMovesTheIntervals) {
  const SaltelliRuns& r = runs();
  const SobolIndices once = saltelli_indices(r.f_a, r.f_b, r.f_ab, kInputs, kResamples, 1);
  const SobolIndices again = saltelli_indices(r.f_a, r.f_b, r.f_ab, kInputs, kResamples, 1);
  EXPECT_TRUE(same_bits(once.first, again.first));
  EXPECT_TRUE(same_bits(once.total, again.total));
  EXPECT_TRUE(same_bits(once.first_ci, again.first_ci));
  EXPECT_TRUE(same_bits(once.total_ci, again.total_ci));
  EXPECT_EQ(std::memcmp(&once.variance, &again.variance, sizeof(double)), 0);

  const SobolIndices other = saltelli_indices(r.f_a, r.f_b, r.f_ab, kInputs, kResamples, 2);
  EXPECT_TRUE(same_bits(once.first, other.first));
  EXPECT_TRUE(same_bits(once.total, other.total));
  for (std::size_t e = 0; e < 2 * kInputs; ++e) {
    EXPECT_NE(once.first_ci[e], other.first_ci[e]) << e;
    EXPECT_NE(once.total_ci[e], other.total_ci[e]) << e;
  }
}

// The bootstrap recipe, recomputed here on a small design: resample r takes
// block floor(u N) for u = counter_uniform(seed, r, j, 7), and the interval
// is the type-7 percentile of the resample values. With 2 resamples the
// bounds are x_min + 0.025 (x_max - x_min) and x_min + 0.975 (x_max - x_min).
// The total index in Janon's textbook form here (raw moments), in deviations
// in the code: the same value up to the cancellation of moments of size
// ~V + mean^2 ~ 15 against differences of ~V: agreement to 1e-10.
TEST(Ishigami, BootstrapFollowsTheDocumentedRecipe) {
  const std::size_t base = 64;
  const SaltelliRuns r = ishigami_runs(base, 3);
  const std::uint64_t seed = 99;
  const SobolIndices s = saltelli_indices(r.f_a, r.f_b, r.f_ab, kInputs, 2, seed);

  std::vector<double> first[kInputs], total[kInputs];
  for (std::uint64_t resample = 0; resample < 2; ++resample) {
    std::vector<std::size_t> blocks(base);
    for (std::size_t j = 0; j < base; ++j) {
      const double u = counter_uniform(seed, resample, j, 7);
      blocks[j] = std::min(static_cast<std::size_t>(std::floor(u * base)), base - 1);
    }
    double mean = 0.0;
    for (const std::size_t j : blocks) mean += r.f_a[j] + r.f_b[j];
    mean /= 2.0 * base;
    double v = 0.0;
    for (const std::size_t j : blocks)
      v += (r.f_a[j] - mean) * (r.f_a[j] - mean) + (r.f_b[j] - mean) * (r.f_b[j] - mean);
    v /= 2.0 * base;
    for (unsigned i = 0; i < kInputs; ++i) {
      double si = 0.0, pair_mean = 0.0;
      for (const std::size_t j : blocks) {
        const double ab = r.f_ab[j * kInputs + i];
        si += (r.f_b[j] - mean) * (ab - r.f_a[j]);
        pair_mean += r.f_a[j] + ab;
      }
      pair_mean /= 2.0 * base;
      // Janon et al. 2014: 1 - (mean(y y') - m^2) / (mean((y^2 + y'^2) / 2) - m^2)
      // for the pair y = f(A), y' = f(AB_i), m their mean, written out as such.
      double product = 0.0, squares = 0.0;
      for (const std::size_t j : blocks) {
        const double y = r.f_a[j], y2 = r.f_ab[j * kInputs + i];
        product += y * y2;
        squares += 0.5 * (y * y + y2 * y2);
      }
      const double m2 = pair_mean * pair_mean;
      first[i].push_back(si / base / v);
      total[i].push_back(1.0 - (product / base - m2) / (squares / base - m2));
    }
  }
  const auto low = [](const std::vector<double>& x) {
    const double lo = std::min(x[0], x[1]), hi = std::max(x[0], x[1]);
    return lo + 0.025 * (hi - lo);
  };
  const auto high = [](const std::vector<double>& x) {
    const double lo = std::min(x[0], x[1]), hi = std::max(x[0], x[1]);
    return lo + 0.975 * (hi - lo);
  };
  for (unsigned i = 0; i < kInputs; ++i) {
    EXPECT_NEAR(s.first_ci[2 * i], low(first[i]), 1e-12) << i;
    EXPECT_NEAR(s.first_ci[2 * i + 1], high(first[i]), 1e-12) << i;
    EXPECT_NEAR(s.total_ci[2 * i], low(total[i]), 1e-10) << i;
    EXPECT_NEAR(s.total_ci[2 * i + 1], high(total[i]), 1e-10) << i;
  }

  // No resamples: point estimates only.
  const SobolIndices none = saltelli_indices(r.f_a, r.f_b, r.f_ab, kInputs, 0, seed);
  EXPECT_TRUE(same_bits(none.first, s.first));
  for (std::size_t e = 0; e < 2 * kInputs; ++e) {
    EXPECT_TRUE(std::isnan(none.first_ci[e])) << e;
    EXPECT_TRUE(std::isnan(none.total_ci[e])) << e;
  }
}

// A constant response has zero variance: the indices are undefined, so NaN
// (exact check), and so are the intervals.
TEST(Ishigami, ZeroVarianceGivesNaN) {
  const std::size_t base = 32;
  const std::vector<double> f_a(base, 2.5), f_b(base, 2.5), f_ab(base * kInputs, 2.5);
  const SobolIndices s = saltelli_indices(f_a, f_b, f_ab, kInputs, 20, 1);
  EXPECT_EQ(s.variance, 0.0);
  EXPECT_EQ(s.base_samples, base);
  for (unsigned i = 0; i < kInputs; ++i) {
    EXPECT_TRUE(std::isnan(s.first[i])) << i;
    EXPECT_TRUE(std::isnan(s.total[i])) << i;
  }
  for (std::size_t e = 0; e < 2 * kInputs; ++e) {
    EXPECT_TRUE(std::isnan(s.first_ci[e])) << e;
    EXPECT_TRUE(std::isnan(s.total_ci[e])) << e;
  }
}

TEST(Ishigami, RefusesMismatchedSizes) {
  const std::vector<double> three(3, 1.0), two(2, 1.0), nine(9, 1.0);
  EXPECT_THROW(saltelli_indices(three, two, nine, 3, 0, 1), std::invalid_argument);
  EXPECT_THROW(saltelli_indices(three, three, two, 3, 0, 1), std::invalid_argument);
  EXPECT_THROW(rank_sensitivity(nine, 2, three), std::invalid_argument);
}

}  // namespace
