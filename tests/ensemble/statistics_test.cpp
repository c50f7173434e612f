// Ensemble statistics, perturbations and the [ensemble] reader
// (mpi/ensemble/statistics.*, perturbation.*, read_ensemble.cpp,
// sample_runner.*).
//
//  * RealEnsemble*: a small real ensemble (double pendulum, 3 perturbations,
//    60 Latin-hypercube samples, 51 output times) run serially through
//    SampleRunner and calibrated exactly as the driver does; the streaming
//    statistics are compared with a direct long-double computation over the
//    kept trajectories, and must not depend on the order of the samples nor
//    on how they are split into accumulators.
//  * Edge*: synthetic calibrations: unperturbed columns, values outside the
//    pilot range, deviations beyond kMaxScaledDeviation, signed zeros.
//  * Perturbation*: every target kind changes exactly its field.
//  * ReadEnsemble*: bad [ensemble] input is refused with a JobError naming
//    the field.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "ensemble/ensemble_spec.hpp"
#include "ensemble/sample_runner.hpp"
#include "ensemble/statistics.hpp"
#include "job/job.hpp"
#include "job/job_error.hpp"

namespace {

using namespace treedyn;
using namespace treedyn::ensemble;

// ---------------------------------------------------------------------------
// A small real ensemble, computed once.

// Two rods (double pendulum), released at 60 and 90 degrees with a spin of
// the lower rod about x, so the motion is three-dimensional. Perturbed: the
// upper rod's release angle (normal, 2 deg), the lower rod's mass (scaled by
// U(0.8, 1.2)) and its initial spin (normal 0.3 +- 0.1 rad/s).
// 1 s at 0.02 s: 51 output times.
const char* kPendulumJob = R"(title = "statistics test pendulum"

[[body]]
name = "upper"
shape = "cylinder"
radius = 0.02
length = 1.0
mass = 1.0
parent = "base"
joint_on_child = [0.0, 0.0, 0.5]
orientation = { type = "axis_angle", axis = [0, 1, 0], angle = 60, unit = "deg" }

[[body]]
name = "lower"
shape = "cylinder"
radius = 0.02
length = 1.0
mass = 1.0
parent = "upper"
joint_on_parent = [0.0, 0.0, -0.5]
joint_on_child = [0.0, 0.0, 0.5]
orientation = { type = "axis_angle", axis = [0, 1, 0], angle = 90, unit = "deg" }
angular_velocity = { value = [0.3, 0.0, 0.0], frame = "inertial", unit = "rad/s" }

[integrator]
method = "cvode_adams"
rtol = 1e-9
atol = 1e-11

[output]
end_time = 1.0
step = 0.02
quantities = ["orientation", "angular_velocity", "com_position", "energy", "base"]

[ensemble]
samples = 60
seed = 11
design = "latin_hypercube"
pilot_samples = 16
histogram_bins = 32

[[ensemble.perturbation]]
target = "body.upper.rotation.y"
distribution = "normal"
std = 2.0
unit = "deg"

[[ensemble.perturbation]]
target = "body.lower.mass"
distribution = "uniform"
lower = 0.8
upper = 1.2
mode = "scale"

[[ensemble.perturbation]]
target = "body.lower.angular_velocity.x"
distribution = "normal"
mean = 0.3
std = 0.1
)";

// The driver's fallback unit: per column, the largest |nominal| over time.
std::vector<double> column_scales(const std::vector<double>& nominal, std::size_t columns) {
  std::vector<double> scale(columns, 0.0);
  for (std::size_t e = 0; e < nominal.size(); ++e)
    scale[e % columns] = std::max(scale[e % columns], std::abs(nominal[e]));
  return scale;
}

struct RealEnsemble {
  Job job;
  EnsembleSpec spec;
  std::size_t times = 0, columns = 0;
  std::vector<double> nominal;
  std::vector<double> pilot_low, pilot_high;
  std::vector<std::vector<double>> trajectories;  // every sample, index order
  Calibration calibration;
};

// Built exactly as mpi/parallel/driver.cpp does on one rank: nominal run
// (k = 0, nominal = true), pilot deviations from samples 0..pilot-1, then
// calibrate() with the per-column scales.
const RealEnsemble& real_ensemble() {
  static const RealEnsemble ensemble = [] {
    RealEnsemble r;
    r.job = parse_job(kPendulumJob, "statistics_test.toml");
    r.spec = read_ensemble(r.job);
    SampleRunner runner(r.job, r.spec);
    r.times = runner.times();
    r.columns = runner.layout().columns;
    const std::size_t entries = r.times * r.columns;
    const SampleRecord nominal = runner.run(0, true, r.nominal);
    if (nominal.status != SampleStatus::ok) throw std::runtime_error("nominal run failed");
    r.pilot_low.assign(entries, std::numeric_limits<double>::infinity());
    r.pilot_high.assign(entries, -std::numeric_limits<double>::infinity());
    for (std::uint64_t k = 0; k < r.spec.samples; ++k) {
      std::vector<double> trajectory;
      const SampleRecord rec = runner.run(k, false, trajectory);
      if (rec.status != SampleStatus::ok)
        throw std::runtime_error("sample " + std::to_string(k) + " failed: " + rec.reason);
      if (k < r.spec.pilot_samples)
        for (std::size_t e = 0; e < entries; ++e) {
          r.pilot_low[e] = std::min(r.pilot_low[e], trajectory[e] - r.nominal[e]);
          r.pilot_high[e] = std::max(r.pilot_high[e], trajectory[e] - r.nominal[e]);
        }
      r.trajectories.push_back(std::move(trajectory));
    }
    r.calibration = calibrate(r.nominal, r.pilot_low, r.pilot_high, column_scales(r.nominal, r.columns),
                              r.columns, r.spec.histogram_bins);
    return r;
  }();
  return ensemble;
}

EnsembleStatistics accumulate(const RealEnsemble& r, const std::vector<std::size_t>& order) {
  EnsembleStatistics s(r.times, r.columns, r.spec.histogram_bins, r.calibration);
  for (std::size_t k : order) s.add_sample(r.trajectories[k]);
  return s;
}

std::vector<std::size_t> index_order(std::size_t n) {
  std::vector<std::size_t> order(n);
  for (std::size_t k = 0; k < n; ++k) order[k] = k;
  return order;
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

// Bitwise equality of every raw array of two accumulators.
void expect_identical(EnsembleStatistics& a, EnsembleStatistics& b, const std::string& what) {
  EXPECT_TRUE(same_bits(a.sums(), b.sums())) << what << ": sums";
  EXPECT_TRUE(same_bits(a.square_sums(), b.square_sums())) << what << ": square sums";
  EXPECT_TRUE(same_bits(a.minima(), b.minima())) << what << ": minima";
  EXPECT_TRUE(same_bits(a.maxima(), b.maxima())) << what << ": maxima";
  EXPECT_TRUE(same_bits(a.counts(), b.counts())) << what << ": histogram counts";
  EXPECT_TRUE(same_bits(a.out_of_range_counts(), b.out_of_range_counts())) << what << ": out of range";
  EXPECT_EQ(a.sample_count(), b.sample_count()) << what << ": samples";
}

// The setup itself: all 60 samples ran, the spec is what the text says, and
// the ensemble really spreads (otherwise the comparisons below test little).
TEST(Statistics, RealEnsembleSetup) {
  const RealEnsemble& r = real_ensemble();
  EXPECT_EQ(r.spec.samples, 60u);
  EXPECT_EQ(r.spec.pilot_samples, 16u);
  EXPECT_EQ(r.spec.perturbations.size(), 3u);
  EXPECT_EQ(r.times, 51u);
  EXPECT_EQ(r.columns, 8u + 6u + 6u + 4u + 9u);
  ASSERT_EQ(r.trajectories.size(), 60u);
  for (const auto& t : r.trajectories) ASSERT_EQ(t.size(), r.times * r.columns);
  std::size_t spread = 0;
  for (std::size_t e = 0; e < r.nominal.size(); ++e) spread += r.pilot_high[e] > r.pilot_low[e];
  std::printf("%zu times x %zu columns, %zu of %zu entries spread in the pilot\n", r.times, r.columns,
              spread, r.nominal.size());
  EXPECT_GT(spread, r.nominal.size() / 2);
}

// Mean, std (n - 1), min, max and quantiles of every entry against a direct
// computation over the 60 kept trajectories.
//
// Accuracy of the fixed-point sums (S = calibration.scale[e], d = x - c):
//  * mean: each d / S is rounded twice in double (subtraction, division) and
//    truncated to 2^-62 in the sum, so |error| <= ~2.2e-16 max|d| + 2^-62 S.
//    Tolerance: 1e-12 |mean| + 1e-13 max(S, max|d|).
//  * variance: each (d / S)^2 is truncated to 2^-40 (kSquareBits), i.e. the
//    sample variance is biased low by at most 2^-40 S^2 n / (n - 1); the
//    double rounding of d / S adds ~4.4e-16 relative. So we compare the
//    VARIANCE: |std_lib^2 - var| <= 1e-12 var + 1.1 * 2^-40 S^2 n/(n-1)
//    + 1e-14 mean((d/S)^2) S^2. As a std this is relative ~1e-12 when
//    std >~ S, but up to 2^-20 S absolute when std << S (a hard limit of
//    40 fraction bits; see the printed worst cases).
//  * min, max: exact.
//  * quantile(q): the exact empirical quantile with the library's definition
//    is the sorted value at position ceil(q n) - 1 (smallest x with at least
//    q n samples <= x). When it lies inside the histogram range
//    [low, low + bins width), the histogram quantile lies in the same bin, so
//    |difference| <= width (times 1 + 1e-9 for the rounding of bin edges).
//    Outside the range it must lie in the same under/overflow segment
//    ([min, low] or [high, max]).
TEST(Statistics, RealEnsembleMatchesDirectComputation) {
  const RealEnsemble& r = real_ensemble();
  const std::size_t n = r.trajectories.size();
  EnsembleStatistics s = accumulate(r, index_order(n));
  ASSERT_EQ(s.samples(), n);
  const int bins = r.spec.histogram_bins;
  const double qs[] = {0.05, 0.1, 0.25, 0.5, 0.75, 0.9, 0.95};
  double worst_mean_rel = 0.0, worst_mean_scaled = 0.0, worst_std_rel = 0.0,
         worst_std_scaled = 0.0, worst_var_scaled = 0.0, worst_quantile_bins = 0.0,
         worst_std_ratio = 0.0;
  std::size_t quantiles_inside = 0, quantiles_outside = 0, out_of_range = 0;
  std::vector<long double> x(n);
  for (std::size_t e = 0; e < s.entries(); ++e) {
    for (std::size_t k = 0; k < n; ++k) x[k] = r.trajectories[k][e];
    const double c = r.calibration.center[e], S = r.calibration.scale[e];
    out_of_range += s.out_of_range(e);
    ASSERT_EQ(s.count(e), n) << "entry " << e;  // nothing out of range in this ensemble
    long double sum = 0.0L, max_dev = 0.0L, mean_sq_scaled = 0.0L;
    for (long double v : x) {
      sum += v;
      max_dev = std::max(max_dev, std::abs(v - c));
      mean_sq_scaled += (v - c) * (v - c) / (static_cast<long double>(S) * S);
    }
    mean_sq_scaled /= n;
    const long double mean = sum / n;
    long double ss = 0.0L;
    for (long double v : x) ss += (v - mean) * (v - mean);
    const long double var = ss / (n - 1);
    const long double sd = std::sqrt(var);

    const double mean_tol = 1e-12 * std::abs(static_cast<double>(mean)) +
                            1e-13 * std::max<double>(S, static_cast<double>(max_dev));
    EXPECT_NEAR(s.mean(e), static_cast<double>(mean), mean_tol) << "entry " << e << " S " << S;
    const long double mean_err = std::abs(s.mean(e) - mean);
    if (mean != 0.0L) worst_mean_rel = std::max(worst_mean_rel, static_cast<double>(mean_err / std::abs(mean)));
    worst_mean_scaled = std::max(worst_mean_scaled, static_cast<double>(mean_err / S));

    const long double lib_sd = s.std_dev(e);
    const long double S2 = static_cast<long double>(S) * S;
    const long double var_tol = 1e-12L * var + 1.1L * std::ldexp(1.0L, -40) * S2 * n / (n - 1) +
                                1e-14L * mean_sq_scaled * S2;
    EXPECT_LE(std::abs(lib_sd * lib_sd - var), var_tol)
        << "entry " << e << ": std " << static_cast<double>(lib_sd) << " vs " << static_cast<double>(sd)
        << ", S " << S;
    if (sd > 0.0L && std::abs(lib_sd - sd) / sd > worst_std_rel) {
      worst_std_rel = static_cast<double>(std::abs(lib_sd - sd) / sd);
      worst_std_ratio = static_cast<double>(sd / S);
    }
    worst_std_scaled = std::max(worst_std_scaled, static_cast<double>(std::abs(lib_sd - sd) / S));
    worst_var_scaled = std::max(worst_var_scaled, static_cast<double>(std::abs(lib_sd * lib_sd - var) / S2));

    // min, max: exact.
    const double mn = static_cast<double>(*std::min_element(x.begin(), x.end()));
    const double mx = static_cast<double>(*std::max_element(x.begin(), x.end()));
    EXPECT_EQ(s.min(e), mn) << "entry " << e;
    EXPECT_EQ(s.max(e), mx) << "entry " << e;

    // Histogram: all samples counted once.
    std::uint64_t total = 0;
    for (std::uint32_t h : s.histogram(e)) total += h;
    EXPECT_EQ(total, n) << "entry " << e;

    // Quantiles.
    std::vector<double> sorted(n);
    for (std::size_t k = 0; k < n; ++k) sorted[k] = r.trajectories[k][e];
    std::sort(sorted.begin(), sorted.end());
    const double low = s.bin_edge(e, 0), high = s.bin_edge(e, bins), width = r.calibration.width[e];
    for (double q : qs) {
      const double target = q * static_cast<double>(n);
      const auto position = static_cast<std::size_t>(std::ceil(target)) - 1;
      const double exact = sorted[position];
      const double got = s.quantile(e, q);
      ASSERT_TRUE(std::isfinite(got)) << "entry " << e << " q " << q;
      EXPECT_GE(got, mn);
      EXPECT_LE(got, mx);
      if (exact >= low && exact < high) {
        ++quantiles_inside;
        EXPECT_LE(std::abs(got - exact), width * (1.0 + 1e-9))
            << "entry " << e << " q " << q << ": histogram " << got << ", exact " << exact
            << ", bin width " << width;
        worst_quantile_bins = std::max(worst_quantile_bins, std::abs(got - exact) / width);
      } else {
        ++quantiles_outside;
        if (exact < low) {
          EXPECT_LE(got, low) << "entry " << e << " q " << q;
        } else {
          EXPECT_GE(got, high) << "entry " << e << " q " << q;
        }
      }
    }
  }
  EXPECT_EQ(out_of_range, 0u);
  std::printf("mean: max relative error %.3g, max error / S %.3g\n", worst_mean_rel, worst_mean_scaled);
  std::printf("std:  max relative error %.3g (at std / S = %.3g), max error / S %.3g, "
              "max |variance error| / S^2 %.3g (2^-40 = %.3g)\n",
              worst_std_rel, worst_std_ratio, worst_std_scaled, worst_var_scaled, std::ldexp(1.0, -40));
  std::printf("quantiles: %zu inside the histogram range (max error %.3f bin widths), %zu outside\n",
              quantiles_inside, worst_quantile_bins, quantiles_outside);
}

// Entries the pilot saw no spread in (e.g. the upper rod's angular velocity
// at t = 0, every "base" column of this fixed base): the fixed-point unit is
// still positive and finite, the std is exactly 0 and the mean exactly the
// nominal value (the deviations are exactly 0).
TEST(Statistics, RealEnsembleUnperturbedEntries) {
  const RealEnsemble& r = real_ensemble();
  EnsembleStatistics s = accumulate(r, index_order(r.trajectories.size()));
  std::size_t unperturbed = 0;
  for (std::size_t e = 0; e < s.entries(); ++e) {
    EXPECT_GT(r.calibration.scale[e], 0.0) << "entry " << e;
    EXPECT_TRUE(std::isfinite(r.calibration.scale[e])) << "entry " << e;
    EXPECT_GT(r.calibration.width[e], 0.0) << "entry " << e;
    bool constant = true;
    for (const auto& t : r.trajectories) constant = constant && t[e] == r.nominal[e];
    if (r.pilot_low[e] == 0.0 && r.pilot_high[e] == 0.0 && constant) {
      ++unperturbed;
      EXPECT_EQ(s.std_dev(e), 0.0) << "entry " << e;
      EXPECT_EQ(s.mean(e), r.nominal[e]) << "entry " << e;
      EXPECT_EQ(s.quantile(e, 0.5), r.nominal[e]) << "entry " << e;
    }
  }
  std::printf("%zu unperturbed entries\n", unperturbed);
  EXPECT_GE(unperturbed, r.times * 9);  // at least the 9 "base" columns
}

// The same 60 samples added in 5 shuffled orders, and split into 4 unequal
// accumulators merged in 3 different groupings, give bitwise identical raw
// arrays (memcmp): sums, square sums, minima, maxima, histogram counts,
// out-of-range counts and the sample count. No tolerance: the claim is exact.
TEST(Statistics, RealEnsembleOrderIndependent) {
  const RealEnsemble& r = real_ensemble();
  const std::size_t n = r.trajectories.size();
  EnsembleStatistics reference = accumulate(r, index_order(n));
  std::mt19937_64 rng(12345);
  for (int shuffle = 0; shuffle < 5; ++shuffle) {
    std::vector<std::size_t> order = index_order(n);
    std::shuffle(order.begin(), order.end(), rng);
    EnsembleStatistics s = accumulate(r, order);
    expect_identical(reference, s, "shuffle " + std::to_string(shuffle));
  }
  std::vector<std::size_t> reversed = index_order(n);
  std::reverse(reversed.begin(), reversed.end());
  EnsembleStatistics backwards = accumulate(r, reversed);
  expect_identical(reference, backwards, "reversed");

  // Split (shuffled) into parts of 7, 23, 1 and 29 samples.
  std::vector<std::size_t> order = index_order(n);
  std::shuffle(order.begin(), order.end(), rng);
  const std::size_t cuts[] = {0, 7, 30, 31, 60};
  auto part = [&](int i) {
    return accumulate(r, std::vector<std::size_t>(order.begin() + static_cast<long>(cuts[i]),
                                                  order.begin() + static_cast<long>(cuts[i + 1])));
  };
  {  // ((a + b) + c) + d
    EnsembleStatistics a = part(0), b = part(1), c = part(2), d = part(3);
    a.merge(b);
    a.merge(c);
    a.merge(d);
    expect_identical(reference, a, "((a+b)+c)+d");
  }
  {  // d + (c + (b + a))
    EnsembleStatistics a = part(0), b = part(1), c = part(2), d = part(3);
    b.merge(a);
    c.merge(b);
    d.merge(c);
    expect_identical(reference, d, "d+(c+(b+a))");
  }
  {  // (a + c) + (d + b), merged into an empty accumulator
    EnsembleStatistics a = part(0), b = part(1), c = part(2), d = part(3);
    a.merge(c);
    d.merge(b);
    EnsembleStatistics empty(r.times, r.columns, r.spec.histogram_bins, r.calibration);
    empty.merge(d);
    empty.merge(a);
    expect_identical(reference, empty, "(a+c)+(d+b)");
  }
}

// ---------------------------------------------------------------------------
// Synthetic edge cases

// 3 times x 3 columns:
//   column 0: perturbed (pilot deviations [-0.1, 0.2]);
//   column 1: unperturbed, nominal 5, -7, 6 (pilot deviations all exactly 0);
//   column 2: unperturbed and identically zero;
// and a pilot that saw nothing at all for entry (time 2, column 0)
// (deviations +inf / -inf). Every scale and bin width is positive and finite;
// the unperturbed column's unit is 2^-10 of its largest |nominal| (7); 10
// samples equal to the nominal give std exactly 0 and mean exactly nominal.
TEST(Statistics, EdgeUnperturbedColumnsHavePositiveScaleAndZeroStd) {
  const std::size_t times = 3, columns = 3;
  const int bins = 16;
  const std::vector<double> nominal = {1.0, 5.0, 0.0, 2.0, -7.0, 0.0, 3.0, 6.0, 0.0};
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<double> lo = {-0.1, 0.0, 0.0, -0.1, 0.0, 0.0, inf, 0.0, 0.0};
  const std::vector<double> hi = {0.2, 0.0, 0.0, 0.2, 0.0, 0.0, -inf, 0.0, 0.0};
  const std::vector<double> column_scale = {3.0, 7.0, 0.0};
  const Calibration cal = calibrate(nominal, lo, hi, column_scale, columns, bins);
  for (std::size_t e = 0; e < nominal.size(); ++e) {
    EXPECT_GT(cal.scale[e], 0.0) << "entry " << e;
    EXPECT_TRUE(std::isfinite(cal.scale[e])) << "entry " << e;
    EXPECT_GT(cal.width[e], 0.0) << "entry " << e;
    EXPECT_TRUE(std::isfinite(cal.width[e])) << "entry " << e;
    EXPECT_LE(cal.low[e], nominal[e]) << "entry " << e;
    EXPECT_GE(cal.low[e] + bins * cal.width[e], nominal[e]) << "entry " << e;
  }
  EXPECT_EQ(cal.scale[0], 0.2);                     // largest |pilot deviation|
  EXPECT_EQ(cal.scale[1], std::ldexp(7.0, -10));    // fallback of column 1
  EXPECT_EQ(cal.scale[6], std::ldexp(3.0, -10));    // nothing seen: fallback of column 0

  EnsembleStatistics s(times, columns, bins, cal);
  for (int k = 0; k < 10; ++k) s.add_sample(nominal);
  for (std::size_t e = 0; e < nominal.size(); ++e) {
    EXPECT_EQ(s.count(e), 10u);
    EXPECT_EQ(s.std_dev(e), 0.0) << "entry " << e;
    EXPECT_EQ(s.mean(e), nominal[e]) << "entry " << e;
    EXPECT_EQ(s.min(e), nominal[e]);
    EXPECT_EQ(s.max(e), nominal[e]);
    EXPECT_EQ(s.quantile(e, 0.05), nominal[e]);
    EXPECT_EQ(s.quantile(e, 0.95), nominal[e]);
  }
}

// Pilot deviations [-1, 1] around nominal 10 with 8 bins: histogram range
// [8.5, 11.5), width 0.375. Samples far outside (-50, 8, 100, 1000, and 11.5
// exactly at the upper edge) go to the under/overflow bins; every quantile
// is inside [min, max], non-decreasing in q, and a quantile whose rank falls
// in the underflow (overflow) lies in [min, low] ([high, max]). Exact.
TEST(Statistics, EdgeValuesOutsideThePilotRange) {
  const std::vector<double> nominal = {10.0};
  const Calibration cal = calibrate(nominal, std::vector<double>{-1.0}, std::vector<double>{1.0},
                                    std::vector<double>{10.0}, 1, 8);
  EXPECT_EQ(cal.low[0], 8.5);
  EXPECT_EQ(cal.width[0], 0.375);
  EnsembleStatistics s(1, 1, 8, cal);
  const double values[] = {10.0, 10.2, 9.9, 9.0, 11.0, -50.0, 100.0, 1000.0, 8.0, 11.5};
  for (double v : values) s.add_sample(std::vector<double>{v});
  const auto h = s.histogram(0);
  ASSERT_EQ(h.size(), 10u);
  EXPECT_EQ(h[0], 2u);  // -50, 8
  EXPECT_EQ(h[9], 3u);  // 100, 1000, 11.5
  std::uint64_t inside = 0;
  for (int b = 1; b <= 8; ++b) inside += h[static_cast<std::size_t>(b)];
  EXPECT_EQ(inside, 5u);
  EXPECT_EQ(s.min(0), -50.0);
  EXPECT_EQ(s.max(0), 1000.0);
  double previous = -std::numeric_limits<double>::infinity();
  for (int i = 1; i < 1000; ++i) {
    const double q = i / 1000.0;
    const double x = s.quantile(0, q);
    EXPECT_GE(x, -50.0) << "q " << q;
    EXPECT_LE(x, 1000.0) << "q " << q;
    EXPECT_GE(x, previous) << "q " << q;
    previous = x;
    if (q * 10 <= 2.0) {
      EXPECT_LE(x, 8.5) << "q " << q;  // rank in the underflow
    }
    if (q * 10 > 7.0) {
      EXPECT_GE(x, 11.5) << "q " << q;  // rank in the overflow
    }
  }
  // All mass far outside on both sides: still clamped to [min, max].
  EnsembleStatistics t(1, 1, 8, cal);
  t.add_sample(std::vector<double>{-1e6});
  t.add_sample(std::vector<double>{1e6});
  for (double q : {1e-9, 0.25, 0.5, 0.75, 1.0 - 1e-9}) {
    EXPECT_GE(t.quantile(0, q), -1e6);
    EXPECT_LE(t.quantile(0, q), 1e6);
  }
}

// Scale S = 1 (pilot deviations [-1, 1] around 0): |d| / S = 2^20 exactly is
// kept; 2^20 (1 + 2^-20) and -3 * 2^20 are out of range: counted in
// out_of_range(), left out of count(), mean and std (checked exactly against
// the kept values, which are exactly representable), but still in min, max
// and the histogram.
TEST(Statistics, EdgeDeviationsBeyondTheFixedPointRange) {
  const std::vector<double> nominal = {0.0};
  const Calibration cal = calibrate(nominal, std::vector<double>{-1.0}, std::vector<double>{1.0},
                                    std::vector<double>{1.0}, 1, 8);
  ASSERT_EQ(cal.scale[0], 1.0);
  const double limit = EnsembleStatistics::kMaxScaledDeviation;
  ASSERT_EQ(limit, 1048576.0);
  EnsembleStatistics s(1, 1, 8, cal);
  const double kept[] = {0.5, -0.25, limit, 1.0};
  const double dropped[] = {limit * (1.0 + 0x1.0p-20), -3.0 * limit};
  for (double v : kept) s.add_sample(std::vector<double>{v});
  for (double v : dropped) s.add_sample(std::vector<double>{v});
  EXPECT_EQ(s.samples(), 6u);
  EXPECT_EQ(s.out_of_range(0), 2u);
  EXPECT_EQ(s.count(0), 4u);
  const double mean = (0.5 - 0.25 + limit + 1.0) / 4.0;
  EXPECT_EQ(s.mean(0), mean);
  long double ss = 0.0L;
  for (double v : kept) ss += (v - static_cast<long double>(mean)) * (v - static_cast<long double>(mean));
  // The square of 2^20 is 2^40: exact in 40 fraction bits; all squares here
  // are dyadic with few bits, so the variance is exact up to long double
  // rounding (relative 1e-15).
  EXPECT_NEAR(s.std_dev(0), std::sqrt(static_cast<double>(ss / 3.0L)), 1e-15 * std::sqrt(static_cast<double>(ss / 3.0L)));
  EXPECT_EQ(s.min(0), -3.0 * limit);
  EXPECT_EQ(s.max(0), limit * (1.0 + 0x1.0p-20));
  std::uint64_t total = 0;
  for (std::uint32_t c : s.histogram(0)) total += c;
  EXPECT_EQ(total, 6u);
  // Merging keeps the split: out_of_range adds, count follows.
  EnsembleStatistics t(1, 1, 8, cal);
  t.add_sample(std::vector<double>{-2.0 * limit});
  t.add_sample(std::vector<double>{0.75});
  s.merge(t);
  EXPECT_EQ(s.out_of_range(0), 3u);
  EXPECT_EQ(s.count(0), 5u);
  EXPECT_DOUBLE_EQ(s.mean(0), (0.5 - 0.25 + limit + 1.0 + 0.75) / 5.0);
}

// Bitwise order independence of min and max when an entry holds both +0.0
// and -0.0 (a component that is exactly zero, computed as -(0) in some
// samples): the stored minimum's sign bit must not depend on the order the
// samples arrive in (nor on which rank saw which). Exact (memcmp).
TEST(Statistics, EdgeSignedZeroMinMaxOrderIndependent) {
  const std::vector<double> nominal = {0.0};
  const Calibration cal = calibrate(nominal, std::vector<double>{0.0}, std::vector<double>{0.0},
                                    std::vector<double>{1.0}, 1, 8);
  EnsembleStatistics a(1, 1, 8, cal), b(1, 1, 8, cal);
  a.add_sample(std::vector<double>{0.0});
  a.add_sample(std::vector<double>{-0.0});
  b.add_sample(std::vector<double>{-0.0});
  b.add_sample(std::vector<double>{0.0});
  EXPECT_TRUE(same_bits(a.minima(), b.minima()))
      << "min: " << std::signbit(a.min(0)) << " vs " << std::signbit(b.min(0)) << " (sign bits)";
  EXPECT_TRUE(same_bits(a.maxima(), b.maxima()))
      << "max: " << std::signbit(a.max(0)) << " vs " << std::signbit(b.max(0)) << " (sign bits)";
}

// ---------------------------------------------------------------------------
// Perturbations: every target changes exactly its field.

const char* kTargetsJob = R"(title = "perturbation targets"

[environment]
gravity = [0.1, -0.2, -9.81]

[base]
type = "harmonic"
offset = [0.0, 0.0, 0.1]
x = [{ amplitude = 0.01, frequency = 2.0 }]
z = [{ amplitude = 0.02, frequency = 5.0, phase = 30, unit = "deg" }, { amplitude = 0.005, frequency = 11.0 }]

[[body]]
name = "upper"
shape = "box"
size = [0.1, 0.2, 1.0]
mass = 2.0
parent = "base"
joint_on_child = [0.0, 0.0, 0.5]
orientation = { type = "bryant123", angles = [10, 20, 30], unit = "deg" }
angular_velocity = { value = [0.1, 0.2, 0.3], frame = "inertial" }
spring = { stiffness = 3.0, damping = 0.1 }

[[body]]
name = "lower"
shape = "cylinder"
radius = 0.05
length = 0.8
mass = 1.0
parent = "upper"
joint_on_parent = [0.01, 0.02, -0.5]
joint_on_child = [0.0, 0.0, 0.4]
orientation = { type = "axis_angle", axis = [0, 1, 0], angle = 90, unit = "deg" }
angular_velocity = { value = [0.4, 0.5, 0.6], frame = "inertial" }
spring = { stiffness = [[3.0, 0.1, 0.0], [0.1, 4.0, 0.0], [0.0, 0.0, 5.0]], damping = 0.2 }

[output]
end_time = 0.1
step = 0.05

[ensemble]
samples = 4

[[ensemble.perturbation]]
target = "body.lower.mass"
distribution = "uniform"
lower = 0.5
upper = 1.5

[[ensemble.perturbation]]
target = "body.lower.mass"
distribution = "normal"
std = 0.1
mode = "add"

[[ensemble.perturbation]]
target = "body.lower.mass"
distribution = "lognormal"
sigma = 0.1
mode = "scale"

[[ensemble.perturbation]]
target = "body.upper.inertia_scale"
distribution = "uniform"
lower = 0.9
upper = 1.1

[[ensemble.perturbation]]
target = "body.lower.joint_on_child.z"
distribution = "normal"
std = 0.01
mode = "add"

[[ensemble.perturbation]]
target = "body.lower.joint_on_parent.x"
distribution = "normal"
mean = 0.01
std = 0.001

[[ensemble.perturbation]]
target = "body.upper.orientation"
distribution = "normal"
std = 2.0
unit = "deg"

[[ensemble.perturbation]]
target = "body.lower.rotation.z"
distribution = "normal"
std = 0.1
unit = "rad"

[[ensemble.perturbation]]
target = "body.lower.angular_velocity.y"
distribution = "normal"
std = 10.0
unit = "deg/s"
mode = "add"

[[ensemble.perturbation]]
target = "joint.lower.stiffness"
distribution = "uniform"
lower = 0.5
upper = 2.0
mode = "scale"

[[ensemble.perturbation]]
target = "joint.lower.damping"
distribution = "uniform"
lower = 0.0
upper = 0.1
mode = "add"

[[ensemble.perturbation]]
target = "joint.upper.stiffness"
distribution = "uniform"
lower = 1.0
upper = 5.0

[[ensemble.perturbation]]
target = "base.z[2].amplitude"
distribution = "uniform"
lower = 0.5
upper = 1.5
mode = "scale"

[[ensemble.perturbation]]
target = "base.z[1].frequency"
distribution = "normal"
std = 0.5
mode = "add"

[[ensemble.perturbation]]
target = "base.x[1].phase"
distribution = "uniform"
lower = 0.0
upper = 360.0
unit = "deg"

[[ensemble.perturbation]]
target = "gravity.z"
distribution = "normal"
mean = -9.81
std = 0.01

[[ensemble.perturbation]]
target = "gravity.x"
distribution = "normal"
std = 0.01
mode = "add"
)";

// Exact field-by-field equality of two model descriptions and states.
void expect_same(const ModelSpec& a, const TreeState& sa, const ModelSpec& b, const TreeState& sb,
                 const std::string& what) {
  ASSERT_EQ(a.bodies.size(), b.bodies.size());
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    EXPECT_EQ(a.bodies[i].mass, b.bodies[i].mass) << what << ": mass of body " << i;
    EXPECT_TRUE(a.bodies[i].inertia == b.bodies[i].inertia) << what << ": inertia of body " << i;
  }
  ASSERT_EQ(a.joints.size(), b.joints.size());
  for (std::size_t j = 0; j < a.joints.size(); ++j) {
    EXPECT_TRUE(a.joints[j].on_parent == b.joints[j].on_parent) << what << ": on_parent " << j;
    EXPECT_TRUE(a.joints[j].on_child == b.joints[j].on_child) << what << ": on_child " << j;
    EXPECT_TRUE(a.joints[j].spring.stiffness == b.joints[j].spring.stiffness) << what << ": stiffness " << j;
    EXPECT_TRUE(a.joints[j].spring.damping == b.joints[j].spring.damping) << what << ": damping " << j;
    EXPECT_TRUE(a.joints[j].spring.reference.coeffs() == b.joints[j].spring.reference.coeffs())
        << what << ": reference " << j;
  }
  EXPECT_TRUE(a.gravity == b.gravity) << what << ": gravity";
  const auto* ha = std::get_if<HarmonicBase>(&a.base_motion);
  const auto* hb = std::get_if<HarmonicBase>(&b.base_motion);
  ASSERT_EQ(ha == nullptr, hb == nullptr);
  if (ha) {
    EXPECT_TRUE(ha->offset == hb->offset) << what << ": base offset";
    for (int axis = 0; axis < 3; ++axis) {
      ASSERT_EQ(ha->axes[axis].size(), hb->axes[axis].size());
      for (std::size_t k = 0; k < ha->axes[axis].size(); ++k) {
        EXPECT_EQ(ha->axes[axis][k].amplitude, hb->axes[axis][k].amplitude) << what << " axis " << axis << " term " << k;
        EXPECT_EQ(ha->axes[axis][k].frequency, hb->axes[axis][k].frequency) << what << " axis " << axis << " term " << k;
        EXPECT_EQ(ha->axes[axis][k].phase, hb->axes[axis][k].phase) << what << " axis " << axis << " term " << k;
      }
    }
  }
  const auto* ca = std::get_if<ConstantAccelerationBase>(&a.base_motion);
  const auto* cb = std::get_if<ConstantAccelerationBase>(&b.base_motion);
  ASSERT_EQ(ca == nullptr, cb == nullptr);
  if (ca) {
    EXPECT_TRUE(ca->position == cb->position) << what;
    EXPECT_TRUE(ca->velocity == cb->velocity) << what;
    EXPECT_TRUE(ca->acceleration == cb->acceleration) << what << ": base acceleration";
  }
  ASSERT_EQ(sa.rotation.size(), sb.rotation.size());
  for (std::size_t i = 0; i < sa.rotation.size(); ++i) {
    EXPECT_TRUE(sa.rotation[i] == sb.rotation[i]) << what << ": rotation of body " << i;
    EXPECT_TRUE(sa.angular_velocity[i] == sb.angular_velocity[i]) << what << ": angular velocity " << i;
  }
}

// Rodrigues' formula, written independently of Eigen's AngleAxis.
Mat3 rodrigues(const Vec3& v) {
  const double angle = v.norm();
  const Vec3 a = v / angle;
  Mat3 k;
  k << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return Mat3::Identity() + std::sin(angle) * k + (1.0 - std::cos(angle)) * k * k;
}

// The reader maps every target to the right field, body, joint, axis, term,
// mode and unit; apply() with a chosen value changes exactly that field
// (every other field of the ModelSpec and TreeState compared bitwise
// unchanged). The expected new values are computed by hand; exact except the
// rotations, which are also checked against Rodrigues' formula to 1e-14
// (rounding of a few trigonometric products).
TEST(Statistics, PerturbationChangesExactlyItsField) {
  const Job job = parse_job(kTargetsJob, "targets.toml");
  const EnsembleSpec spec = read_ensemble(job);
  ASSERT_EQ(spec.perturbations.size(), 17u);
  EXPECT_EQ(spec.input_dimensions(), 19u);  // orientation takes 3
  const ModelSpec& m0 = job.model.spec;
  const TreeState& s0 = job.request.initial;
  ASSERT_EQ(m0.bodies[0].name, "upper");
  ASSERT_EQ(m0.bodies[1].name, "lower");
  const int lower_joint = m0.joints[0].child == "lower" ? 0 : 1;
  const int upper_joint = 1 - lower_joint;
  const double deg = std::numbers::pi / 180.0;
  using F = Perturbation::Field;
  using M = Perturbation::Mode;

  struct Case {
    F field;
    int body;
    int axis;
    int term;
    M mode;
    double unit;
    std::vector<double> values;
    std::function<void(ModelSpec&, TreeState&)> expect;
  };
  const std::vector<Case> cases = {
      {F::mass, 1, 0, 0, M::set, 1.0, {1.3}, [](ModelSpec& m, TreeState&) { m.bodies[1].mass = 1.3; }},
      {F::mass, 1, 0, 0, M::add, 1.0, {0.25}, [](ModelSpec& m, TreeState&) { m.bodies[1].mass = 1.0 + 0.25; }},
      {F::mass, 1, 0, 0, M::scale, 1.0, {1.5}, [](ModelSpec& m, TreeState&) { m.bodies[1].mass = 1.5; }},
      {F::inertia_scale, 0, 0, 0, M::set, 1.0, {1.1},
       [](ModelSpec& m, TreeState&) { m.bodies[0].inertia = m.bodies[0].inertia * 1.1; }},
      {F::joint_on_child, 1, 2, 0, M::add, 1.0, {0.01},
       [&](ModelSpec& m, TreeState&) { m.joints[lower_joint].on_child.z() = 0.4 + 0.01; }},
      {F::joint_on_parent, 1, 0, 0, M::set, 1.0, {-0.03},
       [&](ModelSpec& m, TreeState&) { m.joints[lower_joint].on_parent.x() = -0.03; }},
      {F::orientation, 0, 0, 0, M::set, deg, {0.01, -0.02, 0.03},
       [](ModelSpec&, TreeState& s) {
         const Vec3 v(0.01, -0.02, 0.03);
         s.rotation[0] = Eigen::AngleAxisd(v.norm(), v / v.norm()).toRotationMatrix() * s.rotation[0];
       }},
      {F::rotation, 1, 2, 0, M::set, 1.0, {0.2},
       [](ModelSpec&, TreeState& s) {
         s.rotation[1] = Eigen::AngleAxisd(0.2, Vec3::UnitZ()).toRotationMatrix() * s.rotation[1];
       }},
      {F::angular_velocity, 1, 1, 0, M::add, deg, {0.1},
       [](ModelSpec&, TreeState& s) { s.angular_velocity[1].y() += 0.1; }},
      {F::stiffness, 1, 0, 0, M::scale, 1.0, {2.0},
       [&](ModelSpec& m, TreeState&) { m.joints[lower_joint].spring.stiffness *= 2.0; }},
      {F::damping, 1, 0, 0, M::add, 1.0, {0.05},
       [&](ModelSpec& m, TreeState&) { m.joints[lower_joint].spring.damping += 0.05 * Mat3::Identity(); }},
      {F::stiffness, 0, 0, 0, M::set, 1.0, {4.0},
       [&](ModelSpec& m, TreeState&) { m.joints[upper_joint].spring.stiffness = 4.0 * Mat3::Identity(); }},
      {F::base_amplitude, -1, 2, 1, M::scale, 1.0, {1.2},
       [](ModelSpec& m, TreeState&) { std::get<HarmonicBase>(m.base_motion).axes[2][1].amplitude = 0.005 * 1.2; }},
      {F::base_frequency, -1, 2, 0, M::add, 1.0, {0.5},
       [](ModelSpec& m, TreeState&) { std::get<HarmonicBase>(m.base_motion).axes[2][0].frequency = 5.5; }},
      {F::base_phase, -1, 0, 0, M::set, deg, {1.0},
       [](ModelSpec& m, TreeState&) { std::get<HarmonicBase>(m.base_motion).axes[0][0].phase = 1.0; }},
      {F::gravity, -1, 2, 0, M::set, 1.0, {-9.7}, [](ModelSpec& m, TreeState&) { m.gravity.z() = -9.7; }},
      {F::gravity, -1, 0, 0, M::add, 1.0, {0.02}, [](ModelSpec& m, TreeState&) { m.gravity.x() = 0.1 + 0.02; }},
  };
  ASSERT_EQ(cases.size(), spec.perturbations.size());
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Perturbation& p = spec.perturbations[i];
    const Case& c = cases[i];
    const std::string what = "perturbation " + std::to_string(i + 1) + " (" + p.target + ")";
    EXPECT_EQ(p.field, c.field) << what;
    if (c.body >= 0) {
      EXPECT_EQ(p.body_index, c.body) << what;
    }
    if (c.field == F::joint_on_child || c.field == F::joint_on_parent || c.field == F::stiffness ||
        c.field == F::damping) {
      EXPECT_EQ(p.joint_index, c.body == 1 ? lower_joint : upper_joint) << what;
    }
    EXPECT_EQ(p.axis, c.axis) << what;
    EXPECT_EQ(p.term, c.term) << what;
    EXPECT_EQ(p.mode, c.mode) << what;
    EXPECT_EQ(p.unit, c.unit) << what;
    ASSERT_EQ(static_cast<std::size_t>(p.dimensions()), c.values.size()) << what;

    ModelSpec m = m0, expected_m = m0;
    TreeState s = s0, expected_s = s0;
    p.apply(c.values, m, s);
    c.expect(expected_m, expected_s);
    expect_same(m, s, expected_m, expected_s, what);
  }

  // Rotations, independently: R' R^T is the rotation by the vector.
  {
    ModelSpec m = m0;
    TreeState s = s0;
    const Vec3 v(0.01, -0.02, 0.03);
    spec.perturbations[6].apply(std::vector<double>{v.x(), v.y(), v.z()}, m, s);
    EXPECT_LT((s.rotation[0] * s0.rotation[0].transpose() - rodrigues(v)).norm(), 1e-14);
    spec.perturbations[7].apply(std::vector<double>{0.2}, m, s);
    EXPECT_LT((s.rotation[1] * s0.rotation[1].transpose() - rodrigues(Vec3(0, 0, 0.2))).norm(), 1e-14);
    // A zero rotation vector changes nothing.
    TreeState z = s0;
    spec.perturbations[6].apply(std::vector<double>{0.0, 0.0, 0.0}, m, z);
    EXPECT_TRUE(z.rotation[0] == s0.rotation[0]);
  }

  // sample(): quantile times unit. u = 0.5 of a uniform [0, 360] deg phase
  // is pi rad (exact up to one rounding); of normal(-9.81, 0.01) it is -9.81.
  {
    double out = 0.0;
    const double half = 0.5;
    spec.perturbations[14].sample(std::span<const double>(&half, 1), std::span<double>(&out, 1));
    EXPECT_NEAR(out, std::numbers::pi, 1e-15);
    spec.perturbations[15].sample(std::span<const double>(&half, 1), std::span<double>(&out, 1));
    EXPECT_NEAR(out, -9.81, 1e-14);
    std::vector<double> three(3);
    const std::vector<double> us = {0.5, 0.5, 0.5};
    spec.perturbations[6].sample(us, three);
    EXPECT_EQ(three, std::vector<double>(3, 0.0));
  }
}

// base.acceleration.AXIS on a constant_acceleration base.
TEST(Statistics, PerturbationBaseAcceleration) {
  const std::string text = R"([base]
type = "constant_acceleration"
acceleration = [0.5, 0.0, 1.0]

[[body]]
name = "rod"
shape = "cylinder"
radius = 0.02
length = 1.0
mass = 1.0
parent = "base"
joint_on_child = [0.0, 0.0, 0.5]

[output]
end_time = 0.1
step = 0.05

[ensemble]
samples = 2

[[ensemble.perturbation]]
target = "base.acceleration.z"
distribution = "normal"
std = 0.1
mode = "add"
)";
  const Job job = parse_job(text, "accel.toml");
  const EnsembleSpec spec = read_ensemble(job);
  ASSERT_EQ(spec.perturbations.size(), 1u);
  const Perturbation& p = spec.perturbations[0];
  EXPECT_EQ(p.field, Perturbation::Field::base_acceleration);
  EXPECT_EQ(p.axis, 2);
  ModelSpec m = job.model.spec, expected = job.model.spec;
  TreeState s = job.request.initial;
  p.apply(std::vector<double>{0.25}, m, s);
  std::get<ConstantAccelerationBase>(expected.base_motion).acceleration.z() = 1.25;
  expect_same(m, s, expected, job.request.initial, "base.acceleration.z");
}

// ---------------------------------------------------------------------------
// read_ensemble refuses bad input with a JobError naming the field.

// A one-rod job with a fixed base plus the given [ensemble] text.
std::string rod_job(const std::string& ensemble) {
  return R"([[body]]
name = "rod"
shape = "cylinder"
radius = 0.02
length = 1.0
mass = 1.0
parent = "base"
joint_on_child = [0.0, 0.0, 0.5]

[output]
end_time = 0.1
step = 0.05

)" + ensemble;
}

struct Refusal {
  std::string name;
  std::string ensemble;  // the [ensemble] text
  std::string field;     // JobError::field()
  std::vector<std::string> says;  // substrings of what()
};

// Each case: read_ensemble throws JobError, its field() is exactly the
// offending key's dotted path, and what() holds the listed words (what was
// wrong and what is allowed). Where the key exists in the file the line
// number is the key's line.
TEST(Statistics, ReadEnsembleRefusesBadInput) {
  const std::string p = "[ensemble]\nsamples = 8\n\n[[ensemble.perturbation]]\n";
  const std::vector<Refusal> cases = {
      {"unknown target", p + "target = \"body.rod.colour\"\ndistribution = \"normal\"\nstd = 1.0\n",
       "ensemble.perturbation[1].target", {"'body.rod.colour' is not a target", "allowed targets"}},
      {"unknown body", p + "target = \"body.arm.mass\"\ndistribution = \"normal\"\nstd = 1.0\n",
       "ensemble.perturbation[1].target", {"'arm' is not a body of the model"}},
      {"bad axis", p + "target = \"gravity.w\"\ndistribution = \"normal\"\nstd = 1.0\n",
       "ensemble.perturbation[1].target", {"axis 'w'", "x, y or z"}},
      {"harmonic target on a fixed base",
       p + "target = \"base.z[1].amplitude\"\ndistribution = \"normal\"\nstd = 1.0\n",
       "ensemble.perturbation[1].target", {"harmonic"}},
      {"bad distribution", p + "target = \"body.rod.mass\"\ndistribution = \"gaussian\"\nstd = 1.0\n",
       "ensemble.perturbation[1].distribution", {"\"gaussian\" is not allowed", "\"normal\"", "\"lognormal\""}},
      {"missing std", p + "target = \"body.rod.mass\"\ndistribution = \"normal\"\nmean = 1.0\n",
       "ensemble.perturbation[1].std", {"missing required field"}},
      {"std not positive", p + "target = \"body.rod.mass\"\ndistribution = \"normal\"\nstd = 0.0\n",
       "ensemble.perturbation[1].std", {"must be > 0"}},
      {"uniform lower > upper",
       p + "target = \"body.rod.mass\"\ndistribution = \"uniform\"\nlower = 2.0\nupper = 1.0\n",
       "ensemble.perturbation[1].upper", {"greater than 'lower'"}},
      {"uniform lower == upper",
       p + "target = \"body.rod.mass\"\ndistribution = \"uniform\"\nlower = 1.0\nupper = 1.0\n",
       "ensemble.perturbation[1].upper", {"greater than 'lower'"}},
      {"truncated lower >= upper",
       p + "target = \"body.rod.mass\"\ndistribution = \"truncated_normal\"\nmean = 1.0\nstd = 0.1\n"
           "lower = 1.2\nupper = 0.8\n",
       "ensemble.perturbation[1].upper", {"greater than 'lower'"}},
      {"truncated interval without probability",
       p + "target = \"body.rod.mass\"\ndistribution = \"truncated_normal\"\nmean = 1.0\nstd = 0.01\n"
           "lower = 2.0\nupper = 3.0\n",
       "ensemble.perturbation[1].lower", {"no probability"}},
      {"angle without unit", p + "target = \"body.rod.rotation.x\"\ndistribution = \"normal\"\nstd = 1.0\n",
       "ensemble.perturbation[1].unit", {"\"deg\"", "\"rad\""}},
      {"unit on an SI target",
       p + "target = \"body.rod.mass\"\ndistribution = \"normal\"\nstd = 1.0\nunit = \"g\"\n",
       "ensemble.perturbation[1].unit", {"SI"}},
      {"unit on a scale factor",
       p + "target = \"body.rod.angular_velocity.z\"\ndistribution = \"uniform\"\nlower = 0.99\n"
           "upper = 1.01\nmode = \"scale\"\nunit = \"deg/s\"\n",
       "ensemble.perturbation[1].unit", {"dimensionless"}},
      {"unknown key with suggestion",
       p + "target = \"body.rod.mass\"\ndistribution = \"normal\"\nstdev = 1.0\n",
       "ensemble.perturbation[1].stdev", {"unknown key 'stdev'", "did you mean 'std'?"}},
      {"unknown [ensemble] key with suggestion", "[ensemble]\nsample = 8\n", "ensemble.sample",
       {"unknown key 'sample'", "did you mean 'samples'?"}},
      {"bad mode", p + "target = \"body.rod.mass\"\ndistribution = \"normal\"\nstd = 1.0\nmode = \"mul\"\n",
       "ensemble.perturbation[1].mode", {"\"mul\" is not allowed"}},
      {"mode on a rotation",
       p + "target = \"body.rod.rotation.x\"\ndistribution = \"normal\"\nstd = 1.0\nunit = \"deg\"\n"
           "mode = \"add\"\n",
       "ensemble.perturbation[1].mode", {"not used for this target"}},
      {"missing samples", "[ensemble]\nseed = 3\n", "ensemble.samples", {"missing required field"}},
      {"zero samples", "[ensemble]\nsamples = 0\n", "ensemble.samples", {"at least 1"}},
      {"bad design", "[ensemble]\nsamples = 8\ndesign = \"halton\"\n", "ensemble.design",
       {"\"halton\" is not allowed", "\"sobol\""}},
      {"quantile outside (0, 1)", "[ensemble]\nsamples = 8\nquantiles = [0.5, 1.0]\n", "ensemble.quantiles",
       {"(0, 1)"}},
      {"missing [ensemble]", "", "ensemble", {"missing [ensemble] section"}},
  };
  for (const Refusal& c : cases) {
    const std::string text = rod_job(c.ensemble);
    const Job job = parse_job(text, "bad.toml");
    try {
      read_ensemble(job);
      ADD_FAILURE() << c.name << ": accepted";
    } catch (const JobError& e) {
      std::printf("%-40s %s\n", c.name.c_str(), e.what());
      EXPECT_EQ(e.field(), c.field) << c.name << ": " << e.what();
      for (const std::string& s : c.says)
        EXPECT_NE(std::string(e.what()).find(s), std::string::npos)
            << c.name << ": '" << s << "' not in: " << e.what();
      EXPECT_EQ(e.file(), "bad.toml");
      // The line of the offending key, where it is in the file.
      const std::string key = c.field.substr(c.field.rfind('.') + 1);
      const std::size_t at = text.find("\n" + key + " = ");
      if (at != std::string::npos && text.find("\n" + key + " = ", at + 1) == std::string::npos) {
        const int line = 2 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
        EXPECT_EQ(e.line(), line) << c.name << ": " << e.what();
      }
    } catch (const std::exception& e) {
      ADD_FAILURE() << c.name << ": not a JobError: " << e.what();
    }
  }
}

}  // namespace
