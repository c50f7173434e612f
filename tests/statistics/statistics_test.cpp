// Ensemble statistics (src/statistics/ensemble_statistics.*) on real and synthetic
// samples; perturbations and the [ensemble] reader are in perturbation_test.
//
//  * RealEnsemble*: a small real ensemble (double pendulum, 3 perturbations,
//    60 Latin-hypercube samples, 51 output times) run serially through
//    SampleRunner and calibrated exactly as the driver does; the streaming
//    statistics are compared with a direct long-double computation over the
//    kept trajectories, and must not depend on the order of the samples nor
//    on how they are split into accumulators.
//  * Edge*: synthetic calibrations: unperturbed columns, values outside the
//    pilot range, deviations beyond kMaxScaledDeviation, signed zeros.
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

#include "common/bytes.hpp"
#include "ensemble/sample_runner.hpp"
#include "job/ensemble_spec.hpp"
#include "job/job.hpp"
#include "job/job_error.hpp"
#include "statistics/ensemble_statistics.hpp"

namespace {

using namespace treedyn;
using namespace treedyn::ensemble;
using namespace treedyn::statistics;

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
    for (std::uint64_t k = 0; k < r.spec.runs; ++k) {
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
    r.calibration = calibrate(r.nominal, r.pilot_low, r.pilot_high, column_scales(r.nominal, r.columns), r.columns,
                              r.spec.histogram_bins);
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

// Bitwise equality of two accumulators: their whole states (sums, squares,
// minima, maxima, out-of-range counts, histograms, sample count) as bytes.
void expect_identical(const EnsembleStatistics& a, const EnsembleStatistics& b, const std::string& what) {
  EXPECT_EQ(a.samples(), b.samples()) << what << ": samples";
  EXPECT_TRUE(same_bits(a.state(), b.state())) << what << ": states differ";
}

// The setup itself: all 60 samples ran, the spec is what the text says, and
// the ensemble really spreads (otherwise the comparisons below test little).
TEST(Statistics, RealEnsembleSetup) {
  const RealEnsemble& r = real_ensemble();
  EXPECT_EQ(r.spec.runs, 60u);
  EXPECT_EQ(r.spec.pilot_samples, 16u);
  EXPECT_EQ(r.spec.perturbations.size(), 3u);
  EXPECT_EQ(r.times, 51u);
  EXPECT_EQ(r.columns, 8u + 6u + 6u + 4u + 9u);
  ASSERT_EQ(r.trajectories.size(), 60u);
  for (const auto& t : r.trajectories) ASSERT_EQ(t.size(), r.times * r.columns);
  std::size_t spread = 0;
  for (std::size_t e = 0; e < r.nominal.size(); ++e) spread += r.pilot_high[e] > r.pilot_low[e];
  std::printf("%zu times x %zu columns, %zu of %zu entries spread in the pilot\n", r.times, r.columns, spread,
              r.nominal.size());
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
  double worst_mean_rel = 0.0, worst_mean_scaled = 0.0, worst_std_rel = 0.0, worst_std_scaled = 0.0,
         worst_var_scaled = 0.0, worst_quantile_bins = 0.0, worst_std_ratio = 0.0;
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

    const double mean_tol =
        1e-12 * std::abs(static_cast<double>(mean)) + 1e-13 * std::max<double>(S, static_cast<double>(max_dev));
    EXPECT_NEAR(s.mean(e), static_cast<double>(mean), mean_tol) << "entry " << e << " S " << S;
    const long double mean_err = std::abs(s.mean(e) - mean);
    if (mean != 0.0L) worst_mean_rel = std::max(worst_mean_rel, static_cast<double>(mean_err / std::abs(mean)));
    worst_mean_scaled = std::max(worst_mean_scaled, static_cast<double>(mean_err / S));

    const long double lib_sd = s.std_dev(e);
    const long double S2 = static_cast<long double>(S) * S;
    const long double var_tol =
        1e-12L * var + 1.1L * std::ldexp(1.0L, -40) * S2 * n / (n - 1) + 1e-14L * mean_sq_scaled * S2;
    EXPECT_LE(std::abs(lib_sd * lib_sd - var), var_tol)
        << "entry " << e << ": std " << static_cast<double>(lib_sd) << " vs " << static_cast<double>(sd) << ", S " << S;
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
            << "entry " << e << " q " << q << ": histogram " << got << ", exact " << exact << ", bin width " << width;
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
  std::printf(
      "std:  max relative error %.3g (at std / S = %.3g), max error / S %.3g, "
      "max |variance error| / S^2 %.3g (2^-40 = %.3g)\n",
      worst_std_rel, worst_std_ratio, worst_std_scaled, worst_var_scaled, std::ldexp(1.0, -40));
  std::printf("quantiles: %zu inside the histogram range (max error %.3f bin widths), %zu outside\n", quantiles_inside,
              worst_quantile_bins, quantiles_outside);
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

// The statistics travel as bytes (checkpoints, part files, the MPI
// reduction): parts written with state() and added into an empty
// accumulator give the reference bit for bit, whatever the order. 60
// samples in 128 bins: sparse histogram pieces; a part filled into every bin:
// dense ones. Both layouts are exercised.
TEST(Statistics, RealEnsembleStatesAddUpExactly) {
  const RealEnsemble& r = real_ensemble();
  const std::size_t n = r.trajectories.size();
  const EnsembleStatistics reference = accumulate(r, index_order(n));
  std::vector<std::size_t> order = index_order(n);
  std::mt19937_64 rng(777);
  std::shuffle(order.begin(), order.end(), rng);
  EnsembleStatistics total(r.times, r.columns, r.spec.histogram_bins, r.calibration);
  for (const auto& [first, end] : {std::pair<std::size_t, std::size_t>{40, 60}, {0, 13}, {13, 40}}) {
    const EnsembleStatistics part = accumulate(
        r, std::vector<std::size_t>(order.begin() + static_cast<long>(first), order.begin() + static_cast<long>(end)));
    total.add_state(part.state(), "part");
  }
  expect_identical(reference, total, "added as bytes");
  // One sample's state is sparse: shorter than its dense counts alone.
  const std::size_t dense_counts = r.times * r.columns * (r.spec.histogram_bins + 2) * 4;
  const EnsembleStatistics one = accumulate(r, {5});
  EXPECT_LT(one.state().size(), dense_counts) << "sparse histograms expected";
  EnsembleStatistics one_again(r.times, r.columns, r.spec.histogram_bins, r.calibration);
  one_again.add_state(one.state(), "one");
  expect_identical(one, one_again, "sparse state");

  // Dense: every bin of every entry holds a sample.
  EnsembleStatistics full(r.times, r.columns, r.spec.histogram_bins, r.calibration), copy = full;
  std::vector<double> row(r.times * r.columns);
  for (int b = 0; b < r.spec.histogram_bins; ++b) {
    for (std::size_t e = 0; e < row.size(); ++e) row[e] = r.calibration.low[e] + (b + 0.5) * r.calibration.width[e];
    full.add_sample(row);
  }
  EXPECT_GT(full.state().size(), dense_counts) << "dense histograms expected";
  copy.add_state(full.state(), "full");
  expect_identical(full, copy, "dense state");
}

// A state of another shape or calibration, or a damaged one, is refused
// with DecodeError naming it, never added.
TEST(Statistics, StatesOfAnotherShapeOrCalibrationOrDamagedAreRefused) {
  const RealEnsemble& r = real_ensemble();
  const EnsembleStatistics reference = accumulate(r, index_order(r.trajectories.size()));
  const std::vector<char> state = reference.state();
  auto refused = [&](EnsembleStatistics into, std::span<const char> bytes, const std::string& why) {
    try {
      into.add_state(bytes, "state X");
      ADD_FAILURE() << why << ": accepted";
    } catch (const DecodeError& e) {
      EXPECT_NE(std::string(e.what()).find("state X is damaged"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  };
  refused(EnsembleStatistics(r.times, r.columns, r.spec.histogram_bins + 1, r.calibration), state, "another shape");
  Calibration other = r.calibration;
  other.scale[3] *= 2.0;
  refused(EnsembleStatistics(r.times, r.columns, r.spec.histogram_bins, other), state, "another calibration");
  refused(EnsembleStatistics(r.times, r.columns, r.spec.histogram_bins, r.calibration),
          std::span<const char>(state).first(state.size() - 5), "truncated");
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
  EXPECT_EQ(cal.scale[0], 0.2);                   // largest |pilot deviation|
  EXPECT_EQ(cal.scale[1], std::ldexp(7.0, -10));  // fallback of column 1
  EXPECT_EQ(cal.scale[6], std::ldexp(3.0, -10));  // nothing seen: fallback of column 0

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
  const Calibration cal =
      calibrate(nominal, std::vector<double>{-1.0}, std::vector<double>{1.0}, std::vector<double>{10.0}, 1, 8);
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
  const Calibration cal =
      calibrate(nominal, std::vector<double>{-1.0}, std::vector<double>{1.0}, std::vector<double>{1.0}, 1, 8);
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
  EXPECT_NEAR(s.std_dev(0), std::sqrt(static_cast<double>(ss / 3.0L)),
              1e-15 * std::sqrt(static_cast<double>(ss / 3.0L)));
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

// Pilot deviations near the largest double overflow the histogram's range
// ((high - low) / bins = inf). The calibration must still be usable
// (finite edges, positive widths): with an infinite width the position
// (x - low) / width of a finite value is NaN, and its bin index was out of
// the counters (a heap overflow under ASan before this was fixed). Every
// finite value is then counted once, in the bins or the under/overflow.
// A calibration that is not usable is refused by the statistics.
TEST(Statistics, EdgeAPilotSpreadThatOverflowsStillGivesFiniteBins) {
  const double big = 1.5e308, largest = std::numeric_limits<double>::max();
  const Calibration cal = calibrate(std::vector<double>{0.0, 1.0}, std::vector<double>{-big, -big},
                                    std::vector<double>{big, 0.5}, std::vector<double>{1.0, 1.0}, 2, 8);
  ASSERT_TRUE(cal.usable());
  for (int lanes : {2, 4, 8}) {
    if (!runs_fold_lanes(lanes)) continue;
    SCOPED_TRACE(std::to_string(lanes) + " lanes");
    EnsembleStatistics s(1, 2, 8, cal);
    s.use_fold_lanes(lanes);
    const std::vector<double> values = {largest, -largest, 0.0, 1e300, -1e-300};
    for (double v : values) s.add_sample(std::vector<double>{v, v});
    for (std::size_t e = 0; e < 2; ++e) {
      std::uint64_t total = 0;
      for (std::uint32_t c : s.histogram(e)) total += c;
      EXPECT_EQ(total, values.size()) << "entry " << e;
      EXPECT_EQ(s.min(e), -largest);
      EXPECT_EQ(s.max(e), largest);
    }
  }
  Calibration unusable = cal;
  unusable.width[1] = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(unusable.usable());
  EXPECT_THROW(EnsembleStatistics(1, 2, 8, unusable), std::invalid_argument);
  unusable = cal;
  unusable.low.pop_back();
  EXPECT_THROW(EnsembleStatistics(1, 2, 8, unusable), std::invalid_argument);
}

// Bitwise order independence of min and max when an entry holds both +0.0
// and -0.0 (a component that is exactly zero, computed as -(0) in some
// samples): the stored minimum's sign bit must not depend on the order the
// samples arrive in (nor on which rank saw which). Exact (memcmp).
TEST(Statistics, EdgeSignedZeroMinMaxOrderIndependent) {
  const std::vector<double> nominal = {0.0};
  const Calibration cal =
      calibrate(nominal, std::vector<double>{0.0}, std::vector<double>{0.0}, std::vector<double>{1.0}, 1, 8);
  EnsembleStatistics a(1, 1, 8, cal), b(1, 1, 8, cal);
  a.add_sample(std::vector<double>{0.0});
  a.add_sample(std::vector<double>{-0.0});
  b.add_sample(std::vector<double>{-0.0});
  b.add_sample(std::vector<double>{0.0});
  EXPECT_EQ(std::signbit(a.min(0)), std::signbit(b.min(0))) << "min: sign bits differ";
  EXPECT_EQ(std::signbit(a.max(0)), std::signbit(b.max(0))) << "max: sign bits differ";
  EXPECT_TRUE(same_bits(a.state(), b.state()));
}

// Samples are folded in blocks (ensemble_statistics.hpp): a read after every
// sample folds one sample at a time, a read at the end folds whole blocks
// and a partial one. The states must be the same bits (memcmp), and so
// must the statistics read in between and at the end.
TEST(Statistics, BlocksFoldToTheBitsOfOneSampleAtATime) {
  const RealEnsemble& r = real_ensemble();
  EnsembleStatistics each(r.times, r.columns, r.spec.histogram_bins, r.calibration);
  EnsembleStatistics blocked(r.times, r.columns, r.spec.histogram_bins, r.calibration);
  ASSERT_GT(blocked.block_samples(), 1u) << "this ensemble is small enough for blocks of several samples";
  for (const auto& trajectory : r.trajectories) {
    each.add_sample(trajectory);
    (void)each.min(0);  // folds
    blocked.add_sample(trajectory);
  }
  ASSERT_NE(r.trajectories.size() % blocked.block_samples(), 0u) << "a partial block is folded too";
  expect_identical(each, blocked, "one at a time / in blocks");
  for (std::size_t e = 0; e < each.entries(); ++e) {
    ASSERT_EQ(each.mean(e), blocked.mean(e)) << e;
    ASSERT_EQ(each.quantile(e, 0.5), blocked.quantile(e, 0.5)) << e;
  }
}

// take_sample moves a trajectory's storage into the block instead of
// copying it: the same bits as add_sample (memcmp of the states, partial
// blocks included), and the caller gets storage of the same size back, a
// block's row it can reuse (every row handed back is distinct from the
// ones the block still holds).
TEST(Statistics, TakenSamplesFoldToTheBitsOfCopiedOnes) {
  const RealEnsemble& r = real_ensemble();
  EnsembleStatistics copied(r.times, r.columns, r.spec.histogram_bins, r.calibration);
  EnsembleStatistics taken(r.times, r.columns, r.spec.histogram_bins, r.calibration);
  std::vector<double> buffer;
  for (std::size_t i = 0; i < r.trajectories.size(); ++i) {
    copied.add_sample(r.trajectories[i]);
    buffer = r.trajectories[i];
    const double* given = buffer.data();
    taken.take_sample(buffer);
    ASSERT_EQ(buffer.size(), r.trajectories[i].size());
    ASSERT_NE(buffer.data(), given) << "the storage was taken, not copied";
    if (i % 7 == 3) (void)taken.min(0);  // a partial block folded
    if (i % 7 == 3) (void)copied.min(0);
  }
  expect_identical(copied, taken, "copied / taken");
  std::vector<double> wrong(3);
  EXPECT_THROW(taken.take_sample(wrong), std::invalid_argument);
  EXPECT_EQ(wrong.size(), 3u);
}

// The fold takes its values 2, 4 or 8 at a time and pads a block to a
// whole number of lanes with NaN: the pad must not count. Blocks of 1, 3
// and 5 values (folded by a read) with a value beyond the fixed-point
// range, a NaN and infinities, at every lane width this CPU runs: the ones
// not finite are kept out of everything, the finite one beyond the range
// out of the sums only.
TEST(Statistics, OddBlocksAndValuesThatAreNotFinite) {
  const Calibration cal = calibrate(std::vector<double>{0.0}, std::vector<double>{-1.0}, std::vector<double>{1.0},
                                    std::vector<double>{1.0}, 1, 8);
  const double beyond = 2.0 * EnsembleStatistics::kMaxScaledDeviation, inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int lanes : {2, 4, 8}) {
    if (!runs_fold_lanes(lanes)) continue;
    SCOPED_TRACE(std::to_string(lanes) + " lanes");
    EnsembleStatistics one(1, 1, 8, cal);
    one.use_fold_lanes(lanes);
    one.add_sample(std::vector<double>{0.5});
    EXPECT_EQ(one.out_of_range(0), 0u);
    EXPECT_EQ(one.count(0), 1u);
    EXPECT_EQ(one.mean(0), 0.5);
    EnsembleStatistics three(1, 1, 8, cal);
    three.use_fold_lanes(lanes);
    for (double v : {0.5, nan, 1.0}) three.add_sample(std::vector<double>{v});
    EXPECT_EQ(three.out_of_range(0), 1u);
    EXPECT_EQ(three.count(0), 2u);
    EXPECT_EQ(three.mean(0), 0.75);
    EXPECT_EQ(three.min(0), 0.5);
    EXPECT_EQ(three.max(0), 1.0);
    EnsembleStatistics five(1, 1, 8, cal);
    five.use_fold_lanes(lanes);
    for (double v : {0.5, -inf, beyond, 1.0, inf}) five.add_sample(std::vector<double>{v});
    EXPECT_EQ(five.out_of_range(0), 3u);
    EXPECT_EQ(five.count(0), 2u);
    EXPECT_EQ(five.mean(0), 0.75);
    EXPECT_EQ(five.std_dev(0), std::sqrt(0.125));
    EXPECT_EQ(five.min(0), 0.5);
    EXPECT_EQ(five.max(0), beyond);
    std::uint64_t total = 0;
    for (std::uint32_t c : five.histogram(0)) total += c;
    EXPECT_EQ(total, 3u);  // 0.5, 1.0 and the finite one beyond the range
  }
}

// The fold at every lane width this CPU runs (2 on every x86-64; 4 with
// AVX2, 8 with AVX-512F) must give the same bits (memcmp of the states),
// on the real ensemble and on hostile values: every bin edge and its
// neighbours, values below and above the histogram, beyond the fixed-point
// range, signed zeros, NaN and infinities, in blocks of 1, 2, 3, ...
// samples (each read folds a partial block), over entries that are not a
// whole number of 8 lanes (the last ones folded as a padded tail). The
// widest fold the CPU runs is checked against a direct computation by
// RealEnsembleMatchesDirectComputation.
TEST(Statistics, EveryLaneWidthFoldsToTheSameBits) {
  EXPECT_THROW(EnsembleStatistics(1, 1, 8,
                                  calibrate(std::vector<double>{0.0}, std::vector<double>{-1.0},
                                            std::vector<double>{1.0}, std::vector<double>{1.0}, 1, 8))
                   .use_fold_lanes(3),
               std::invalid_argument);
  const RealEnsemble& r = real_ensemble();
  const std::size_t entries = r.times * r.columns;
  ASSERT_NE(entries % 8, 0u) << "a tail of entries";
  std::vector<std::vector<double>> samples = r.trajectories;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  for (int k = 0; k < 200; ++k) {
    std::vector<double> s(entries);
    for (std::size_t e = 0; e < entries; ++e) {
      const double low = r.calibration.low[e], width = r.calibration.width[e];
      const int edge = static_cast<int>(rng() % static_cast<unsigned>(r.spec.histogram_bins + 3)) - 1;
      const double at_edge = low + edge * width;
      // clang-format off
      switch (rng() % 8) {
        case 0: s[e] = at_edge; break;
        case 1: s[e] = std::nextafter(at_edge, -inf); break;
        case 2: s[e] = std::nextafter(at_edge, inf); break;
        case 3: s[e] = r.calibration.center[e] + unit(rng) * 4.0 * EnsembleStatistics::kMaxScaledDeviation * r.calibration.scale[e]; break;
        case 4: s[e] = (rng() % 2 ? 0.0 : -0.0); break;
        case 5: s[e] = (rng() % 64 == 0 ? (rng() % 2 ? nan : (rng() % 2 ? inf : -inf)) : unit(rng)); break;
        default: s[e] = low + (unit(rng) + 0.5) * r.spec.histogram_bins * width * 1.5; break;
      }
      // clang-format on
    }
    samples.push_back(std::move(s));
  }
  std::vector<char> two_lanes;
  int widths = 0;
  for (int lanes : {2, 4, 8}) {
    if (!runs_fold_lanes(lanes)) continue;
    ++widths;
    EnsembleStatistics stats(r.times, r.columns, r.spec.histogram_bins, r.calibration);
    stats.use_fold_lanes(lanes);
    std::size_t next_read = 1, block = 1;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      stats.add_sample(samples[i]);
      if (i + 1 == next_read) {  // partial blocks of 1, 2, 3, ... samples
        (void)stats.min(0);
        block = block % EnsembleStatistics::kMaxBlock + 1;
        next_read += block;
      }
    }
    if (lanes == 2)
      two_lanes = stats.state();
    else
      EXPECT_TRUE(same_bits(two_lanes, stats.state())) << lanes << " lanes against 2";
  }
  std::printf("[          ] lane widths compared on this CPU: %d (widest %d)\n", widths, widest_fold_lanes());
}

// The fold's rounded sums (block_fold_lanes.inc) against what they
// replace, std::nearbyint (ties to even) and the compiler's double ->
// __int128 conversion, at every lane width this CPU runs: every power of
// two and its neighbours up to 2^100 (the square's limit), halves (ties)
// below and around 2^50 and 2^52, values so small that v / 2^50
// underflows, and a million random values of every magnitude (a sixth of
// them at 2^95-2^100, where v / 2^50 itself is often a tie), each alone
// and in shuffled blocks of 32, and the largest block (64 values of
// 2^100). Exact.
TEST(Statistics, RoundedSumIsNearbyintThenConversionSummed) {
  const auto reference = [](double x) { return static_cast<wide>(std::nearbyint(x)); };
  // clang-format off
  std::vector<double> values = {0.0, -0.0, 0.5, -0.5, 1.5, -1.5, 2.5, -2.5, 0x1p52 - 0.5, 0x1p52 - 1.5,
                                -(0x1p52 - 0.5), 0x1p52, 0x1p52 + 1, 0x1p63, -0x1p63, 0x1p82, -0x1p82,
                                0x1p100, -0x1p100, 0x1p49 + 0.5, 0x1p50 - 0.5, 0x1p50 + 0.5, -(0x1p51 + 0.5),
                                0x1p-1000, -0x1p-1070, std::numeric_limits<double>::denorm_min(), 1e-300};
  // clang-format on
  for (int k = -60; k <= 100; ++k)
    for (double f : {1.0, -1.0}) {
      const double p = f * std::ldexp(1.0, k);
      values.insert(values.end(), {p, std::nextafter(p, 0.0), p + 0.5 * f, p - 0.5 * f});
      if (k < 100) values.push_back(std::nextafter(p, 2 * p));
    }
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-70, 100);
  for (int k = 0; k < 1000000; ++k) values.push_back(std::ldexp(unit(rng), exponent(rng)));
  std::vector<double> shuffled = values;
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  const std::vector<double> largest(EnsembleStatistics::kMaxBlock, 0x1p100);
  int widths = 0;
  for (int lanes : {2, 4, 8}) {
    if (!runs_fold_lanes(lanes)) continue;
    ++widths;
    for (double x : values)
      ASSERT_TRUE(rounded_sum_in_lanes(std::span<const double>(&x, 1), lanes) == reference(x))
          << lanes << " lanes, " << std::hexfloat << x;
    for (std::size_t start = 0; start + 32 <= shuffled.size(); start += 32) {
      wide expected = 0;
      for (std::size_t i = start; i < start + 32; ++i) expected += reference(shuffled[i]);
      ASSERT_TRUE(rounded_sum_in_lanes(std::span<const double>(shuffled.data() + start, 32), lanes) == expected)
          << lanes << " lanes, block at " << start;
    }
    ASSERT_TRUE(rounded_sum_in_lanes(largest, lanes) ==
                static_cast<wide>(largest.size()) * (static_cast<wide>(1) << 100))
        << lanes << " lanes";
  }
  EXPECT_GE(widths, 1);
}

}  // namespace
