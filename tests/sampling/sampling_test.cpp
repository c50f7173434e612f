// Sampling designs and input distributions of the ensemble library
// (src/sampling/design.*, distribution.*).
//
//  * KolmogorovSmirnov: every distribution, pushed through every design,
//    reproduces its declared distribution function.
//  * DistributionRoundTrip / TruncatedNormalStaysInside: quantile and cdf are
//    inverse to each other; the truncated normal never leaves [lower, upper].
//  * LatinHypercube*: every stratum of every dimension is hit exactly once.
//  * PermuteIndex*: the Feistel permutation is a bijection on [0, n).
//  * Sobol*: the unscrambled points are the standard (Joe-Kuo, Gray-code)
//    Sobol sequence, and the scrambled design keeps its net structure.
//  * Reproducibility*: a sample's point is a pure function of (seed, k, d).
//
// Every test prints the numbers it reached (KS statistics, errors) so that a
// run's log can be quoted.
#include <boost/math/distributions/normal.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numeric>
#include <set>
#include <string>
#include <vector>

#include "analysis/sensitivity.hpp"
#include "designs/sample_design.hpp"
#include "sampling/design.hpp"
#include "sampling/distribution.hpp"
#include "sampling/normal_copula.hpp"

namespace {

using treedyn::designs::SampleDesign;
using treedyn::sampling::counter_uniform;
using treedyn::sampling::Design;
using treedyn::sampling::Distribution;
using treedyn::sampling::permute_index;
using treedyn::sampling::sobol_bits;

constexpr Design kDesigns[] = {Design::monte_carlo, Design::latin_hypercube, Design::sobol};

std::string design_name(Design d) { return std::string(name(d)); }

Distribution normal(double mean, double std) {
  Distribution d;
  d.kind = Distribution::Kind::normal;
  d.mean = mean;
  d.std = std;
  return d;
}

Distribution truncated_normal(double mean, double std, double lower, double upper) {
  Distribution d;
  d.kind = Distribution::Kind::truncated_normal;
  d.mean = mean;
  d.std = std;
  d.lower = lower;
  d.upper = upper;
  return d;
}

Distribution uniform(double lower, double upper) {
  Distribution d;
  d.kind = Distribution::Kind::uniform;
  d.lower = lower;
  d.upper = upper;
  return d;
}

Distribution lognormal(double mu, double sigma) {
  Distribution d;
  d.kind = Distribution::Kind::lognormal;
  d.mu = mu;
  d.sigma = sigma;
  return d;
}

// The distributions the KS test uses, one per input dimension of the design.
// The truncated normal is cut asymmetrically (about 31 % of the mass removed,
// more on the left) so that a wrong renormalisation would show.
std::vector<Distribution> test_distributions() {
  return {normal(1.5, 0.3), truncated_normal(0.0, 1.0, -0.5, 2.0), uniform(-2.0, 3.0), lognormal(0.2, 0.5)};
}

// Two-sided Kolmogorov-Smirnov statistic D = sup |F_N(x) - F(x)| of the
// sample against F = dist.cdf.
double ks_statistic(std::vector<double> x, const Distribution& dist) {
  std::sort(x.begin(), x.end());
  const double n = static_cast<double>(x.size());
  double d = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double f = dist.cdf(x[i]);
    d = std::max({d, f - static_cast<double>(i) / n, static_cast<double>(i + 1) / n - f});
  }
  return d;
}

// ---------------------------------------------------------------------------
// Distributions through designs

// N = 2000 points of a 4-dimensional design at a fixed seed, dimension d
// mapped through distribution d by its quantile function; D against the
// declared cdf.
//  * All designs: D < 1.63 / sqrt(N) = 0.0364, the asymptotic 1 % critical
//    value of the KS test for independent samples (for Monte Carlo this is the
//    real test; the seed is fixed, so the outcome is deterministic).
//  * Latin hypercube: one point in each stratum [j/N, (j+1)/N) of u, and
//    F(F^-1(u)) = u up to rounding, so |F_N - F| <= 1/N at every x:
//    D <= 1/N + 1e-9 (1e-9 covers the cdf/quantile rounding, ~1e-15).
//  * Sobol (scrambled, a (0, 1)-sequence in each dimension): the star
//    discrepancy of the first N points of a base-2 (0,1)-sequence is at most
//    about (log2 N + 1) / N; we allow (log2 N + 3) / N = 0.0070.
TEST(Sampling, KolmogorovSmirnov) {
  constexpr std::uint64_t kN = 2000;
  const std::vector<Distribution> dists = test_distributions();
  const double critical = 1.63 / std::sqrt(static_cast<double>(kN));
  for (Design design : kDesigns) {
    const SampleDesign sd(design, 20240611, kN, static_cast<unsigned>(dists.size()));
    std::vector<std::vector<double>> x(dists.size());
    std::vector<double> u(dists.size());
    for (std::uint64_t k = 0; k < kN; ++k) {
      sd.point(k, u);
      for (std::size_t d = 0; d < dists.size(); ++d) x[d].push_back(dists[d].quantile(u[d]));
    }
    for (std::size_t d = 0; d < dists.size(); ++d) {
      const double D = ks_statistic(x[d], dists[d]);
      std::printf("KS %-16s %-60s D = %.6f (1%% critical %.4f, 1/N = %.6f)\n", design_name(design).c_str(),
                  dists[d].describe().c_str(), D, critical, 1.0 / static_cast<double>(kN));
      EXPECT_LT(D, critical) << design_name(design) << " " << dists[d].describe();
      if (design == Design::latin_hypercube) {
        EXPECT_LE(D, 1.0 / static_cast<double>(kN) + 1e-9) << dists[d].describe();
      }
      if (design == Design::sobol) {
        EXPECT_LE(D, (std::log2(static_cast<double>(kN)) + 3.0) / static_cast<double>(kN)) << dists[d].describe();
      }
    }
  }
}

// cdf(quantile(u)) = u on a grid from 1e-9 to 1 - 1e-9, and
// quantile(cdf(x)) = x at interior points.
// Tolerances (from the conditioning, not from the implementation):
//  * |cdf(quantile(u)) - u| <= 1e-13 + 1e-9 * min(u, 1 - u): u near 1 is
//    known only to ~1e-16 absolutely, so 1e-13 absolute; the relative part
//    covers Boost's few-ulp accuracy in the lower tail. The truncated normal
//    is a difference of two normal probabilities (upper-tail ones when the
//    interval lies above the mean) over the interval's mass, which amplifies
//    rounding by (larger probability) / mass: at most 1.5 for the cases here,
//    including the far tails [7, 100] and [-100, -7] (mass 1.28e-12), which
//    only a tail-aware inversion gets right.
//  * |quantile(cdf(x)) - x| <= 1e-9 * max(1, |x|) for x whose cdf is in
//    [1e-6, 1 - 1e-6]: dx = du / f(x), f(x) >~ 1e-6 there, du ~ 1e-16.
TEST(Sampling, DistributionRoundTrip) {
  std::vector<Distribution> dists = test_distributions();
  dists.push_back(normal(-3.0, 1e-3));
  dists.push_back(truncated_normal(10.0, 2.0, 11.0, 30.0));   // only the right tail
  dists.push_back(truncated_normal(0.0, 1.0, 3.0, 5.0));      // far tail, b - a = 1.3e-3
  dists.push_back(truncated_normal(0.0, 1.0, 7.0, 100.0));    // far upper tail, mass 1.3e-12
  dists.push_back(truncated_normal(0.0, 1.0, -100.0, -7.0));  // its mirror
  dists.push_back(uniform(0.9, 1.1));
  dists.push_back(lognormal(-1.0, 0.05));
  std::vector<double> us = {1e-9, 1e-6, 1e-3, 0.01, 0.05,     0.1,      0.25,    0.5,
                            0.75, 0.9,  0.95, 0.99, 1 - 1e-3, 1 - 1e-6, 1 - 1e-9};
  double worst_u = 0.0, worst_x = 0.0;
  for (const Distribution& dist : dists) {
    for (double u : us) {
      const double x = dist.quantile(u);
      ASSERT_TRUE(std::isfinite(x)) << dist.describe() << " u = " << u;
      const double back = dist.cdf(x);
      double amplification = 1.0;
      if (dist.kind == Distribution::Kind::truncated_normal) {
        // The truncated cdf is a difference of normal probabilities on the
        // interval's side of the mean (upper-tail ones above it), divided by
        // the mass: rounding grows by (larger probability) / mass.
        const Distribution full = normal(dist.mean, dist.std);
        if (dist.lower > dist.mean) {
          const double sa = full.cdf(2 * dist.mean - dist.lower), sb = full.cdf(2 * dist.mean - dist.upper);
          amplification = sa / (sa - sb);
        } else {
          const double a = full.cdf(dist.lower), b = full.cdf(dist.upper);
          amplification = b / (b - a);
        }
      }
      const double tolerance = (1e-13 + 1e-9 * std::min(u, 1.0 - u)) * amplification;
      EXPECT_NEAR(back, u, tolerance) << dist.describe() << " x = " << x;
      worst_u = std::max(worst_u, std::abs(back - u));
      // The reverse direction away from the tails.
      if (u >= 1e-6 && u <= 1 - 1e-6) {
        const double again = dist.quantile(dist.cdf(x));
        EXPECT_NEAR(again, x, 1e-9 * std::max(1.0, std::abs(x)) * amplification) << dist.describe() << " u = " << u;
        worst_x = std::max(worst_x, std::abs(again - x) / std::max(1.0, std::abs(x)));
      }
    }
    // Monotone in u.
    for (std::size_t i = 1; i < us.size(); ++i)
      EXPECT_LE(dist.quantile(us[i - 1]), dist.quantile(us[i])) << dist.describe();
  }
  std::printf(
      "round trip: max |cdf(quantile(u)) - u| = %.3g, "
      "max |quantile(cdf(x)) - x| / max(1, |x|) = %.3g\n",
      worst_u, worst_x);
}

// quantile(u) is finite, does not throw, and lies in [lower, upper] for
// every u a design can produce, including the extremes 2^-54 and 1 - 2^-52
// (Monte Carlo's largest value below 1), 2^-33 and 1 - 2^-33 (Sobol), and
// for intervals far in either tail, where the inversion must work with
// upper-tail probabilities (cdf(7) = 1 - 1.28e-12 has only ~4 significant
// digits in double) and cdf(upper) may round to 1. Exact check (no
// tolerance): the library clamps. For the tail intervals the quantile must
// also be strictly increasing along a grid of 2000 u (it would be piecewise
// constant if the inversion lost its digits).
TEST(Sampling, TruncatedNormalStaysInside) {
  const std::vector<Distribution> dists = {
      truncated_normal(0.0, 1.0, -0.5, 2.0),   truncated_normal(10.0, 2.0, 11.0, 30.0),
      truncated_normal(0.0, 1.0, 6.0, 8.0),    truncated_normal(0.0, 1.0, -8.0, -6.0),
      truncated_normal(0.0, 1.0, 7.0, 100.0),  truncated_normal(0.0, 1.0, -100.0, -7.0),
      truncated_normal(0.0, 1.0, 0.0, 100.0),  truncated_normal(0.0, 1.0, -100.0, 0.0),
      truncated_normal(5.0, 0.1, 4.999, 5.001)};
  const std::vector<double> extremes = {0x1.0p-54,   0x1.0p-33,       1e-12,           0.5,
                                        1.0 - 1e-12, 1.0 - 0x1.0p-33, 1.0 - 0x1.0p-52, std::nextafter(1.0, 0.0)};
  auto checked = [](const Distribution& dist, double u, double& x) {
    try {
      x = dist.quantile(u);
    } catch (const std::exception& e) {
      ADD_FAILURE() << dist.describe() << ": quantile(" << u << ") throws: " << e.what();
      return false;
    }
    EXPECT_TRUE(std::isfinite(x)) << dist.describe() << " u = " << u;
    EXPECT_GE(x, dist.lower) << dist.describe() << " u = " << u;
    EXPECT_LE(x, dist.upper) << dist.describe() << " u = " << u;
    return x >= dist.lower && x <= dist.upper;
  };
  for (const Distribution& dist : dists) {
    double x = 0.0;
    for (double u : extremes) checked(dist, u, x);
    for (Design design : kDesigns) {
      const SampleDesign sd(design, 99, 4096, 2);
      for (std::uint64_t k = 0; k < 4096; ++k)
        for (unsigned d = 0; d < 2; ++d)
          ASSERT_TRUE(checked(dist, sd.uniform(k, d), x)) << design_name(design) << " k " << k;
    }
    double previous = -std::numeric_limits<double>::infinity();
    int flat = 0;
    for (int i = 1; i < 2000; ++i) {
      if (!checked(dist, i / 2000.0, x)) break;
      flat += !(x > previous);
      previous = x;
    }
    EXPECT_EQ(flat, 0) << dist.describe() << ": quantile not strictly increasing on the u grid";
  }
}

// ---------------------------------------------------------------------------
// Latin hypercube

// For N in {1, 7, 64, 1000} and 6 dimensions: {floor(u_k,d * N), k < N} is
// exactly {0, ..., N-1} in every dimension (exact integer check), every u is
// in the open interval (0, 1), and (for N >= 7) no two dimensions share a
// permutation (with 6 dimensions and >= 7! permutations a coincidence would
// be a 1-in-300 event for N = 7 and essentially impossible otherwise; the
// seed is fixed).
TEST(Sampling, LatinHypercubeHitsEveryStratumOnce) {
  constexpr unsigned kDims = 6;
  for (std::uint64_t n : {1ULL, 7ULL, 64ULL, 1000ULL}) {
    for (std::uint64_t seed : {1ULL, 12345ULL}) {
      const SampleDesign sd(Design::latin_hypercube, seed, n, kDims);
      std::vector<std::vector<std::uint64_t>> strata(kDims);
      std::vector<double> u(kDims);
      for (std::uint64_t k = 0; k < n; ++k) {
        sd.point(k, u);
        for (unsigned d = 0; d < kDims; ++d) {
          ASSERT_GT(u[d], 0.0);
          ASSERT_LT(u[d], 1.0);
          strata[d].push_back(static_cast<std::uint64_t>(std::floor(u[d] * static_cast<double>(n))));
        }
      }
      for (unsigned d = 0; d < kDims; ++d) {
        std::vector<std::uint64_t> sorted = strata[d];
        std::sort(sorted.begin(), sorted.end());
        std::vector<std::uint64_t> expected(n);
        std::iota(expected.begin(), expected.end(), 0);
        EXPECT_EQ(sorted, expected) << "N = " << n << " seed " << seed << " dimension " << d;
      }
      if (n >= 7) {
        for (unsigned a = 0; a < kDims; ++a)
          for (unsigned b = a + 1; b < kDims; ++b)
            EXPECT_NE(strata[a], strata[b]) << "N = " << n << " dimensions " << a << ", " << b;
      }
    }
  }
}

// ---------------------------------------------------------------------------
// permute_index

// For n from 1 to 70001 (powers of two, their neighbours, odd sizes), three
// (seed, stream) keys: every image is in [0, n) and all images are distinct
// (exact). For n >= 16 the permutation is not the identity, and different
// streams give different permutations. index >= n throws.
TEST(Sampling, PermuteIndexIsABijection) {
  const std::uint64_t sizes[] = {1,   2,   3,    4,    5,    7,    8,    15,    16,    17,    100,  255,
                                 256, 257, 1000, 1023, 1024, 1025, 4097, 12345, 65535, 65536, 70001};
  const std::pair<std::uint64_t, std::uint64_t> keys[] = {{1, 0}, {1, 1}, {0xdeadbeefULL, 42}};
  for (std::uint64_t n : sizes) {
    std::vector<std::vector<std::uint64_t>> images;
    for (auto [seed, stream] : keys) {
      std::vector<std::uint64_t> image(n);
      std::vector<char> seen(n, 0);
      std::uint64_t fixed_points = 0;
      for (std::uint64_t i = 0; i < n; ++i) {
        const std::uint64_t j = permute_index(i, n, seed, stream);
        ASSERT_LT(j, n) << "n = " << n;
        ASSERT_FALSE(seen[j]) << "n = " << n << ": " << j << " hit twice";
        seen[j] = 1;
        image[i] = j;
        fixed_points += j == i;
      }
      if (n >= 16) {
        EXPECT_LT(fixed_points, n) << "identity permutation for n = " << n;
      }
      images.push_back(std::move(image));
      EXPECT_THROW(permute_index(n, n, seed, stream), std::out_of_range);
    }
    if (n >= 16) {
      EXPECT_NE(images[0], images[1]) << "streams 0 and 1 agree for n = " << n;
    }
  }
}

// ---------------------------------------------------------------------------
// Sobol

// The unscrambled points: sobol_bits(k, d, D) / 2^32 for k = 0..7 and
// d = 0..2 must be the standard Sobol sequence in Gray-code order with the
// Joe-Kuo direction numbers, as scipy.stats.qmc.Sobol(d, scramble=False)
// gives it, which starts at the origin:
//   dim 0: 0, .5, .75, .25, .375, .875, .625, .125
//   dim 1: 0, .5, .25, .75, .375, .875, .125, .625
//   dim 2: 0, .5, .25, .75, .625, .125, .875, .375
// (dimension 0 is van der Corput in Gray-code order; dimension 1 has
// polynomial x + 1, m = 1; dimension 2 polynomial x^2 + x + 1, m = 1, 3).
// Exact comparison: the values are dyadic. Also the total dimension count D
// does not change a dimension's values.
TEST(Sampling, SobolMatchesStandardSequence) {
  const double expected[3][8] = {{0, .5, .75, .25, .375, .875, .625, .125},
                                 {0, .5, .25, .75, .375, .875, .125, .625},
                                 {0, .5, .25, .75, .625, .125, .875, .375}};
  for (unsigned total : {3u, 10u}) {
    for (unsigned d = 0; d < 3; ++d) {
      std::string got;
      for (std::uint64_t k = 0; k < 8; ++k) {
        const double x = sobol_bits(k, d, total) * 0x1.0p-32;
        got += std::to_string(x).substr(0, 6) + " ";
        EXPECT_EQ(x, expected[d][k]) << "point " << k << ", dimension " << d << " of " << total;
      }
      std::printf("sobol_bits dim %u (of %u): %s\n", d, total, got.c_str());
    }
  }
}

// Owen scrambling maps a (t, m, s)-net to a (t, m, s)-net, and the first 2^m
// points of the Sobol sequence are a (0, m, 1)-net in each dimension: each of
// the 2^m intervals [j / 2^m, (j + 1) / 2^m) holds exactly one of the first
// 2^m points of the scrambled design, for m = 1..10 and dimensions 0..4.
// Dimensions 0 and 1 together form a (0, m, 2)-net: every elementary box
// [i / 2^a, (i+1) / 2^a) x [j / 2^b, (j+1) / 2^b) with a + b = m holds
// exactly one point. Exact counts, two seeds.
TEST(Sampling, ScrambledSobolKeepsNetStructure) {
  constexpr unsigned kDims = 5;
  constexpr int kMaxM = 10;
  for (std::uint64_t seed : {3ULL, 2024ULL}) {
    const SampleDesign sd(Design::sobol, seed, 1u << kMaxM, kDims);
    std::vector<std::vector<double>> u(1u << kMaxM, std::vector<double>(kDims));
    for (std::uint64_t k = 0; k < u.size(); ++k) sd.point(k, u[k]);
    for (int m = 1; m <= kMaxM; ++m) {
      const std::uint64_t n = std::uint64_t{1} << m;
      for (unsigned d = 0; d < kDims; ++d) {
        std::vector<int> count(n, 0);
        for (std::uint64_t k = 0; k < n; ++k)
          ++count[static_cast<std::size_t>(std::floor(u[k][d] * static_cast<double>(n)))];
        int empty = 0, crowded = 0;
        for (int c : count) empty += c == 0, crowded += c > 1;
        EXPECT_TRUE(empty == 0 && crowded == 0) << "seed " << seed << ", first 2^" << m << " points, dimension " << d
                                                << ": " << empty << " empty and " << crowded << " doubly hit intervals";
      }
      for (int a = 0; a <= m; ++a) {
        const int b = m - a;
        std::vector<int> count(n, 0);
        for (std::uint64_t k = 0; k < n; ++k) {
          const auto i = static_cast<std::uint64_t>(std::floor(std::ldexp(u[k][0], a)));
          const auto j = static_cast<std::uint64_t>(std::floor(std::ldexp(u[k][1], b)));
          ++count[static_cast<std::size_t>((i << b) | j)];
        }
        const auto bad = std::count_if(count.begin(), count.end(), [](int c) { return c != 1; });
        EXPECT_EQ(bad, 0) << "seed " << seed << ", first 2^" << m << " points, boxes 2^-" << a << " x 2^-" << b
                          << " in dimensions 0, 1";
      }
    }
  }
}

// ---------------------------------------------------------------------------
// Reproducibility

// For each design, N = 200, 7 dimensions: sample k's point is bitwise the same
// (memcmp) whether computed alone by a fresh SampleDesign, in forward order,
// in reverse order, interleaved, or dimension by dimension through uniform().
// A different seed changes every sample's point.
TEST(Sampling, PointDependsOnlyOnSeedSampleDimension) {
  constexpr std::uint64_t kN = 200;
  constexpr unsigned kDims = 7;
  for (Design design : kDesigns) {
    const SampleDesign forward(design, 77, kN, kDims);
    std::vector<std::vector<double>> reference(kN, std::vector<double>(kDims));
    for (std::uint64_t k = 0; k < kN; ++k) forward.point(k, reference[k]);

    const SampleDesign reverse(design, 77, kN, kDims);
    std::vector<double> u(kDims);
    for (std::uint64_t k = kN; k-- > 0;) {
      reverse.point(k, u);
      ASSERT_EQ(std::memcmp(u.data(), reference[k].data(), kDims * sizeof(double)), 0)
          << design_name(design) << " reverse order, sample " << k;
    }
    for (std::uint64_t k : {0ULL, 1ULL, 57ULL, 199ULL, 3ULL, 57ULL}) {
      const SampleDesign alone(design, 77, kN, kDims);
      alone.point(k, u);
      ASSERT_EQ(std::memcmp(u.data(), reference[k].data(), kDims * sizeof(double)), 0)
          << design_name(design) << " alone, sample " << k;
      for (unsigned d = kDims; d-- > 0;) {
        const double v = alone.uniform(k, d);
        ASSERT_EQ(std::memcmp(&v, &reference[k][d], sizeof v), 0)
            << design_name(design) << " uniform(), sample " << k << " dimension " << d;
      }
    }
    // Interleaved: even samples forward, odd samples backward, one object.
    const SampleDesign mixed(design, 77, kN, kDims);
    for (std::uint64_t i = 0; i < kN; ++i) {
      const std::uint64_t k = i % 2 == 0 ? i : kN - i;
      mixed.point(k, u);
      ASSERT_EQ(std::memcmp(u.data(), reference[k].data(), kDims * sizeof(double)), 0)
          << design_name(design) << " interleaved, sample " << k;
    }
    // Another seed: every sample moves (every coordinate, in fact, for all
    // but a negligible chance; we require at least one per sample).
    const SampleDesign other(design, 78, kN, kDims);
    std::uint64_t same_coordinates = 0;
    for (std::uint64_t k = 0; k < kN; ++k) {
      other.point(k, u);
      EXPECT_NE(std::memcmp(u.data(), reference[k].data(), kDims * sizeof(double)), 0)
          << design_name(design) << " seeds 77 and 78 agree on sample " << k;
      for (unsigned d = 0; d < kDims; ++d) same_coordinates += u[d] == reference[k][d];
    }
    std::printf("%-16s seeds 77 vs 78: %llu of %llu coordinates equal\n", design_name(design).c_str(),
                static_cast<unsigned long long>(same_coordinates), static_cast<unsigned long long>(kN * kDims));
  }
  // counter_uniform itself: pure, open interval, streams independent.
  EXPECT_EQ(counter_uniform(5, 6, 7, 0), counter_uniform(5, 6, 7, 0));
  EXPECT_NE(counter_uniform(5, 6, 7, 0), counter_uniform(5, 6, 7, 1));
  EXPECT_NE(counter_uniform(5, 6, 7, 0), counter_uniform(6, 6, 7, 0));
}

// ---------------------------------------------------------------------------
// Correlated inputs: a normal copula on each input's own marginal.

using treedyn::sampling::InputCorrelation;
using treedyn::sampling::NormalCopula;

// Spearman's rank correlation of two columns: the project's own
// (analysis/sensitivity.hpp), x as the one input and y as the response.
double spearman(const std::vector<double>& x, const std::vector<double>& y) {
  return treedyn::analysis::rank_sensitivity(x, 1, y).spearman.at(0);
}

// Three inputs with normal, uniform and lognormal marginals, correlated
// pairwise (Spearman 0.6, -0.4 and 0.3 asked; the copula's matrix is
// positive definite), N = 10,000 samples of each design.
//  * Spearman of the drawn values within 0.02 of the asked value. Spearman
//    is a property of the copula alone, so the marginals cannot move it;
//    the sampling error of a rank correlation at N = 10,000 is about
//    (1 - r^2) / sqrt(N) <= 0.01, so 0.02 is 2 standard errors or more; no
//    copula at all misses it by 0.3 or more. For Sobol points, 0.005 (see
//    below) also catches Spearman's value used as the copula's parameter.
//  * Each marginal unchanged: the Kolmogorov-Smirnov statistic against the
//    input's own distribution below the 0.1 % critical value 1.95 / sqrt(N).
//  * The first input of the set keeps its uniforms bit for bit (and so a
//    Latin hypercube's strata: D <= 1/N); the others do not (printed).
TEST(Sampling, CorrelatedInputsHaveTheAskedSpearmanAndKeepTheirMarginals) {
  constexpr std::uint64_t kN = 10000;
  Distribution normal, uniform, lognormal;
  normal.mean = 2.0, normal.std = 0.5;
  uniform.kind = Distribution::Kind::uniform, uniform.lower = -1.0, uniform.upper = 3.0;
  lognormal.kind = Distribution::Kind::lognormal, lognormal.mu = 0.1, lognormal.sigma = 0.8;
  const Distribution dists[] = {normal, uniform, lognormal};
  const double asked[3][3] = {{1, 0.6, 0.3}, {0.6, 1, -0.4}, {0.3, -0.4, 1}};
  std::vector<InputCorrelation> pairs;
  for (unsigned a = 0; a < 3; ++a)
    for (unsigned b = a + 1; b < 3; ++b)
      pairs.push_back({a, b, treedyn::sampling::normal_copula_of_spearman(asked[a][b]), true});
  const NormalCopula copula(3, pairs);
  const double critical = 1.95 / std::sqrt(static_cast<double>(kN));
  for (Design design : kDesigns) {
    const SampleDesign sd(design, 20261202, kN, 3);
    std::vector<std::vector<double>> x(3);
    std::vector<double> u(3), independent(3);
    for (std::uint64_t k = 0; k < kN; ++k) {
      sd.point(k, u);
      independent = u;
      copula.correlate(u);
      EXPECT_EQ(std::memcmp(&u[0], &independent[0], sizeof(double)), 0) << "the first input changed";
      for (std::size_t d = 0; d < 3; ++d) x[d].push_back(dists[d].quantile(u[d]));
    }
    for (unsigned a = 0; a < 3; ++a) {
      const double D = ks_statistic(x[a], dists[a]);
      std::printf("copula %-16s input %u %-36s KS D = %.5f (0.1%% critical %.4f)\n", design_name(design).c_str(), a,
                  dists[a].describe().c_str(), D, critical);
      EXPECT_LT(D, critical) << design_name(design) << " input " << a;
      if (design == Design::latin_hypercube && a == 0) {
        EXPECT_LE(D, 1.0 / kN + 1e-9);
      }
      for (unsigned b = a + 1; b < 3; ++b) {
        const double r = spearman(x[a], x[b]);
        std::printf("copula %-16s Spearman(%u, %u) = %+.4f, asked %+.2f\n", design_name(design).c_str(), a, b, r,
                    asked[a][b]);
        EXPECT_NEAR(r, asked[a][b], 0.02) << design_name(design) << " inputs " << a << ", " << b;
        // Scrambled Sobol points leave far less sampling error (measured
        // 0.0001-0.0002): 0.005 tells the right copula parameter from
        // Spearman's value taken as it (0.012-0.018 off at these values).
        if (design == Design::sobol) {
          EXPECT_NEAR(r, asked[a][b], 0.005) << "inputs " << a << ", " << b;
        }
      }
    }
  }
}

// The copula's parameter and Spearman's correlation are each other's
// inverse, with the textbook values: rho = 1 gives Spearman 1, rho = 0.5
// gives (6/pi) asin(1/4) = 0.4826.
TEST(Sampling, NormalCopulaParameterAndSpearmanConvert) {
  EXPECT_NEAR(treedyn::sampling::spearman_of_normal_copula(1.0), 1.0, 1e-15);
  EXPECT_NEAR(treedyn::sampling::spearman_of_normal_copula(0.5), 0.482584, 1e-6);
  for (double r : {-0.9, -0.3, 0.0, 0.2, 0.75})
    EXPECT_NEAR(treedyn::sampling::spearman_of_normal_copula(treedyn::sampling::normal_copula_of_spearman(r)), r,
                1e-14);
}

// A set that cannot hold (x0 ~ x1 and x1 ~ x2 strongly, x0 ~ x2 strongly
// the other way) is refused; inputs outside every pair keep their bits.
TEST(Sampling, NormalCopulaRefusesAnImpossibleSetAndLeavesOtherInputsAlone) {
  const std::vector<InputCorrelation> impossible = {{0, 1, 0.9, false}, {1, 2, 0.9, false}, {0, 2, -0.9, false}};
  EXPECT_THROW(NormalCopula(3, impossible), std::invalid_argument);
  const NormalCopula copula(4, std::vector<InputCorrelation>{{1, 3, 0.5, false}});
  std::vector<double> u = {0.123, 0.456, 0.789, 0.321}, before = u;
  copula.correlate(u);
  EXPECT_EQ(u[0], before[0]);
  EXPECT_EQ(u[1], before[1]);
  EXPECT_EQ(u[2], before[2]);
  EXPECT_NE(u[3], before[3]);
  // u3' = Phi(0.5 z1 + sqrt(0.75) z3), z = Phi^-1(u), by hand with Boost's normal.
  const boost::math::normal phi;
  const double z = 0.5 * boost::math::quantile(phi, 0.456) + std::sqrt(0.75) * boost::math::quantile(phi, 0.321);
  EXPECT_NEAR(u[3], boost::math::cdf(phi, z), 1e-15);
}

}  // namespace
