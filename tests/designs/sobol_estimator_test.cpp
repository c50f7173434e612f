// Which Sobol' estimators treedyn uses, and why: the published estimators
// from Saltelli's design (A, B and the AB_i runs) compared on functions with
// analytic indices, at the small base sizes an engineer starts with
// (N = 16, 64, 256), over 200 scrambling seeds of the project's own design.
//
//  * first order: Saltelli 2010 (Table 2 (b), f(B) centred), Jansen 1999
//    (Table 2 (c)), Janon et al. 2014 / Martinez 2011 (the correlation of
//    f(B) and f(AB_i));
//  * total: Jansen 1999 (Table 2 (f)), Sobol' 2007 (Table 2 (d), f(A)
//    centred), Janon et al. 2014 (1 - their closed index of all inputs but
//    i, from f(A) and f(AB_i)), Martinez 2011.
//
// The alternatives are written out here from the papers; saltelli_indices
// must equal the chosen ones (Saltelli 2010 first order, Janon total), which
// must have the smallest root-mean-square error over all indices at N = 16
// and 64 on both functions (within 1 %: Janon and Martinez tie). The test also measures how often the reported
// 95 % bootstrap intervals hold the exact index (printed; docs/design.md).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "analysis/sensitivity.hpp"
#include "designs/saltelli/sobol_indices.hpp"
#include "designs/sample_design.hpp"
#include "sampling/design.hpp"

namespace {

using namespace treedyn;
using namespace treedyn::sampling;
using treedyn::designs::saltelli_indices;
using treedyn::designs::SampleDesign;
using treedyn::designs::SobolIndices;

constexpr int kSeeds = 200;
constexpr int kResamples = 1000;

struct Case {
  std::string name;
  unsigned inputs;
  std::function<double(std::span<const double>)> f;  // of uniforms in (0, 1)
  std::vector<double> first, total;                  // analytic
};

// Ishigami (a = 7, b = 0.1) on (-pi, pi)^3; analytic values as in
// sensitivity_test.cpp (Saltelli et al., the Primer, section 4.9).
Case ishigami() {
  const double a = 7.0, b = 0.1, pi = std::numbers::pi, pi4 = std::pow(pi, 4), pi8 = pi4 * pi4;
  const double v = a * a / 8 + b * pi4 / 5 + b * b * pi8 / 18 + 0.5;
  const double v1 = 0.5 * (1 + b * pi4 / 5) * (1 + b * pi4 / 5), v2 = a * a / 8;
  const double v13 = b * b * pi8 * (1.0 / 18 - 1.0 / 50);
  auto f = [=](std::span<const double> u) {
    const double x1 = pi * (2 * u[0] - 1), x2 = pi * (2 * u[1] - 1), x3 = pi * (2 * u[2] - 1);
    return std::sin(x1) + a * std::sin(x2) * std::sin(x2) + b * std::pow(x3, 4) * std::sin(x1);
  };
  return {"Ishigami", 3, f, {v1 / v, v2 / v, 0.0}, {(v1 + v13) / v, v2 / v, v13 / v}};
}

// Sobol's g function, prod (|4 u_i - 2| + a_i) / (1 + a_i), a = (0, 1, 4.5,
// 9, 99, 99): V_i = 1 / (3 (1 + a_i)^2), V = prod (1 + V_i) - 1, and
// ST_i = V_i prod_{k != i} (1 + V_k) / V (Saltelli et al. 2010, section 4).
Case g_function() {
  const std::vector<double> a{0, 1, 4.5, 9, 99, 99};
  std::vector<double> vi(a.size()), first(a.size()), total(a.size());
  double product = 1.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    vi[i] = 1.0 / (3.0 * (1.0 + a[i]) * (1.0 + a[i]));
    product *= 1.0 + vi[i];
  }
  for (std::size_t i = 0; i < a.size(); ++i) {
    first[i] = vi[i] / (product - 1.0);
    total[i] = vi[i] * product / (1.0 + vi[i]) / (product - 1.0);
  }
  auto f = [a](std::span<const double> u) {
    double p = 1.0;
    for (std::size_t i = 0; i < a.size(); ++i) p *= (std::abs(4.0 * u[i] - 2.0) + a[i]) / (1.0 + a[i]);
    return p;
  };
  return {"g function", static_cast<unsigned>(a.size()), f, first, total};
}

struct Runs {
  std::vector<double> a, b, ab;  // f(A), f(B) (N), f(AB_i) (N x D)
};

Runs saltelli_runs(const Case& c, std::size_t base, std::uint64_t seed) {
  const std::uint64_t block = saltelli_block(c.inputs);
  const SampleDesign design(Design::saltelli, seed, base * block, c.inputs);
  Runs r{std::vector<double>(base), std::vector<double>(base), std::vector<double>(base * c.inputs)};
  std::vector<double> u(c.inputs);
  for (std::uint64_t k = 0; k < base * block; ++k) {
    design.point(k, u);
    const double y = c.f(u);
    const SaltelliPlace at = saltelli_place(k, c.inputs);
    if (at.role == SaltelliRole::a)
      r.a[at.base] = y;
    else if (at.role == SaltelliRole::b)
      r.b[at.base] = y;
    else
      r.ab[at.base * c.inputs + at.unit] = y;
  }
  return r;
}

double mean(const std::vector<double>& x) {
  double s = 0.0;
  for (const double v : x) s += v;
  return s / static_cast<double>(x.size());
}

// Pearson correlation of x and column i of the N x D matrix y.
double correlation(const std::vector<double>& x, const std::vector<double>& y, unsigned d, unsigned i) {
  const std::size_t n = x.size();
  double mx = 0.0, my = 0.0;
  for (std::size_t j = 0; j < n; ++j) mx += x[j], my += y[j * d + i];
  mx /= static_cast<double>(n), my /= static_cast<double>(n);
  double sxy = 0.0, sxx = 0.0, syy = 0.0;
  for (std::size_t j = 0; j < n; ++j) {
    const double dx = x[j] - mx, dy = y[j * d + i] - my;
    sxy += dx * dy, sxx += dx * dx, syy += dy * dy;
  }
  return sxy / std::sqrt(sxx * syy);
}

// Janon's closed index from a pair (y, y') sharing some inputs, in its
// published raw-moment form.
double janon(const std::vector<double>& y, const std::vector<double>& ab, unsigned d, unsigned i) {
  const double n = static_cast<double>(y.size());
  double product = 0.0, squares = 0.0, sum = 0.0;
  for (std::size_t j = 0; j < y.size(); ++j) {
    const double y2 = ab[j * d + i];
    product += y[j] * y2, squares += 0.5 * (y[j] * y[j] + y2 * y2), sum += 0.5 * (y[j] + y2);
  }
  const double m = sum / n;
  return (product / n - m * m) / (squares / n - m * m);
}

// clang-format off
enum Estimator { kSaltelli2010, kJansenFirst, kJanonFirst, kMartinezFirst,
                 kJansenTotal, kSobol2007Total, kJanonTotal, kMartinezTotal, kEstimators };
const std::array<const char*, kEstimators> kNames{
    "S Saltelli 2010", "S Jansen 1999", "S Janon 2014", "S Martinez 2011",
    "ST Jansen 1999", "ST Sobol' 2007", "ST Janon 2014", "ST Martinez 2011"};
// clang-format on
bool is_first(int e) { return e < kJansenTotal; }

// Every estimator's value for input i of runs r.
std::array<double, kEstimators> estimates(const Runs& r, unsigned d, unsigned i) {
  const std::size_t n = r.a.size();
  const double nn = static_cast<double>(n);
  std::vector<double> both(r.a);
  both.insert(both.end(), r.b.begin(), r.b.end());
  const double m = mean(both), ma = mean(r.a);
  double v = 0.0;
  for (const double y : both) v += (y - m) * (y - m);
  v /= 2.0 * nn;
  double saltelli = 0.0, jansen_first = 0.0, jansen_total = 0.0, sobol = 0.0;
  for (std::size_t j = 0; j < n; ++j) {
    const double ab = r.ab[j * d + i];
    saltelli += (r.b[j] - m) * (ab - r.a[j]);
    jansen_first += (r.b[j] - ab) * (r.b[j] - ab);
    jansen_total += (r.a[j] - ab) * (r.a[j] - ab);
    sobol += (r.a[j] - ma) * (r.a[j] - ab);
  }
  return {saltelli / nn / v,
          1.0 - jansen_first / (2.0 * nn) / v,
          janon(r.b, r.ab, d, i),
          correlation(r.b, r.ab, d, i),
          jansen_total / (2.0 * nn) / v,
          sobol / nn / v,
          1.0 - janon(r.a, r.ab, d, i),
          1.0 - correlation(r.a, r.ab, d, i)};
}

struct Study {
  std::array<double, kEstimators> rmse{};
  double first_coverage = 0.0, total_coverage = 0.0;  // of the reported intervals
};

Study study(const Case& c, std::size_t base) {
  Study s;
  std::array<double, kEstimators> squares{};
  int inside_first = 0, inside_total = 0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const Runs r = saltelli_runs(c, base, static_cast<std::uint64_t>(seed));
    const SobolIndices reported = saltelli_indices(r.a, r.b, r.ab, c.inputs, kResamples, 7);
    for (unsigned i = 0; i < c.inputs; ++i) {
      const std::array<double, kEstimators> e = estimates(r, c.inputs, i);
      // The code computes the chosen two (Janon in deviations, not raw moments).
      EXPECT_NEAR(reported.first[i], e[kSaltelli2010], 1e-12) << c.name << " " << base << " " << seed << " " << i;
      EXPECT_NEAR(reported.total[i], e[kJanonTotal], 1e-9) << c.name << " " << base << " " << seed << " " << i;
      for (int k = 0; k < kEstimators; ++k) {
        const double exact = is_first(k) ? c.first[i] : c.total[i];
        squares[k] += (e[k] - exact) * (e[k] - exact);
      }
      inside_first += reported.first_ci[2 * i] <= c.first[i] && c.first[i] <= reported.first_ci[2 * i + 1];
      inside_total += reported.total_ci[2 * i] <= c.total[i] && c.total[i] <= reported.total_ci[2 * i + 1];
    }
  }
  const double count = static_cast<double>(kSeeds) * c.inputs;
  for (int k = 0; k < kEstimators; ++k) s.rmse[k] = std::sqrt(squares[k] / count);
  s.first_coverage = inside_first / count;
  s.total_coverage = inside_total / count;
  return s;
}

double best_of(const Study& s, std::initializer_list<int> which) {
  double best = INFINITY;
  for (const int k : which) best = std::min(best, s.rmse[k]);
  return best;
}

TEST(SobolEstimators, TheChosenOnesHaveTheSmallestErrorAtSmallN) {
  for (const Case& c : {ishigami(), g_function()}) {
    for (const std::size_t base : {16u, 64u, 256u}) {
      const Study s = study(c, base);
      std::printf("%s, N = %zu, %d seeds: root-mean-square error over the %u inputs\n", c.name.c_str(), base, kSeeds,
                  c.inputs);
      for (int k = 0; k < kEstimators; ++k) std::printf("  %-17s %.4f\n", kNames[k], s.rmse[k]);
      std::printf("  reported 95 %% intervals hold the exact index: first order %.1f %%, total %.1f %%\n",
                  100.0 * s.first_coverage, 100.0 * s.total_coverage);
      if (base > 64) continue;  // the choice is made for small N; at 256 they come together
      // Within 1 %: Janon's and Martinez's totals are asymptotically the same
      // estimator, and tie to 0.1 % here.
      EXPECT_LE(s.rmse[kSaltelli2010], 1.01 * best_of(s, {kSaltelli2010, kJansenFirst, kJanonFirst, kMartinezFirst}))
          << c.name << " N = " << base;
      EXPECT_LE(s.rmse[kJanonTotal], 1.01 * best_of(s, {kJansenTotal, kSobol2007Total, kJanonTotal, kMartinezTotal}))
          << c.name << " N = " << base;
    }
  }
}

}  // namespace
