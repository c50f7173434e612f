// The serial answers: response reductions on hand-made trajectories, the
// Wilson interval against its defining quadratic, exceedance and convergence
// with failed samples, and the layout of Saltelli's design.
#include "analysis/answers.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "designs/sample_design.hpp"
#include "output/response.hpp"
#include "sampling/design.hpp"

namespace {

using namespace treedyn;
using namespace treedyn::analysis;
using namespace treedyn::sampling;
using treedyn::designs::SampleDesign;
constexpr double kInf = std::numeric_limits<double>::infinity();

Response response(Response::Reduce reduce, double parameter = 0.0) {
  Response r;
  r.name = "r";
  r.column_index = 1;
  r.reduce = reduce;
  r.time = parameter;
  r.threshold = parameter;
  return r;
}

// Two columns; column 1 is x(t) = 0, 2, 1, 4, 3 at t = 0, 1, 2, 3, 4.
const std::vector<double> kTimes{0.0, 1.0, 2.0, 3.0, 4.0};
const std::vector<double> kTrajectory{9, 0, 9, 2, 9, 1, 9, 4, 9, 3};

double value(Response::Reduce reduce, double parameter = 0.0) {
  return evaluate(response(reduce, parameter), kTrajectory, kTimes, 2);
}

// Exact: each is a few operations on small integers.
TEST(Response, EveryReductionOnAHandMadeTrajectory) {
  using R = Response::Reduce;
  EXPECT_EQ(value(R::final), 3.0);
  EXPECT_EQ(value(R::min), 0.0);
  EXPECT_EQ(value(R::max), 4.0);
  EXPECT_EQ(value(R::mean), 2.0);
  EXPECT_DOUBLE_EQ(value(R::rms), std::sqrt(30.0 / 5.0));
  EXPECT_EQ(value(R::at_time, 2.0), 1.0);  // at an output time: the value there
  EXPECT_EQ(value(R::at_time, 2.5), 2.5);  // between: linear
  EXPECT_EQ(value(R::at_time, 4.0), 3.0);
  EXPECT_EQ(value(R::first_time_above, 1.0), 0.5);  // crosses 1 between t = 0 and 1
  EXPECT_EQ(value(R::first_time_above, 3.0), 2.0 + 2.0 / 3.0);
  EXPECT_EQ(value(R::first_time_above, 5.0), kInf);  // never
  EXPECT_EQ(value(R::first_time_above, -1.0), 0.0);  // already above at the start
  EXPECT_EQ(value(R::first_time_below, 1.5), 0.0);   // x(0) = 0 is below
  EXPECT_EQ(value(R::first_time_below, -1.0), kInf);
}

TEST(Response, ColumnReductionsKeepTheFirstTimeOfATie) {
  const std::vector<double> x{5, 1, 7, 1, 7};  // one column
  const std::vector<Reduction> all{Reduction::final, Reduction::min, Reduction::max, Reduction::argmin_time,
                                   Reduction::argmax_time};
  std::vector<double> out;
  reduce_columns(x, kTimes, 1, all, out);
  EXPECT_EQ(out, (std::vector<double>{7, 1, 7, 1.0, 2.0}));
}

// Several columns, reductions in any order and repeated: each column's
// values are what that column alone gives (its own one-column reduction).
TEST(Response, ColumnReductionsOfEveryColumnAreThoseOfTheColumnAlone) {
  const std::size_t columns = 3, T = kTimes.size();
  const std::vector<double> x{5, -2, 0, 1, 4, 0, 7, -2, 3, 1, 9, 3, 7, 9, -1};  // times x columns
  const std::vector<Reduction> which{Reduction::argmax_time, Reduction::min,         Reduction::final,
                                     Reduction::max,         Reduction::argmin_time, Reduction::min};
  std::vector<double> out;
  reduce_columns(x, kTimes, columns, which, out);
  ASSERT_EQ(out.size(), which.size() * columns);
  for (std::size_t c = 0; c < columns; ++c) {
    std::vector<double> column, alone;
    for (std::size_t k = 0; k < T; ++k) column.push_back(x[k * columns + c]);
    reduce_columns(column, kTimes, 1, which, alone);
    for (std::size_t r = 0; r < which.size(); ++r) EXPECT_EQ(out[r * columns + c], alone[r]) << "column " << c;
  }
}

// Columns of small integers (ties are common), NaNs and zeros of both
// signs; the last column holds only zeros (so a zero is its extreme), and
// `nan_start` starts with a NaN.
std::vector<double> extremes_trajectory(std::size_t T, std::size_t columns, std::size_t nan_start) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> x(T * columns);
  std::uint64_t state = 12345 + T * columns;
  for (std::size_t i = 0; i < x.size(); ++i) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    const auto r = static_cast<int>(state >> 59);  // 0 .. 31
    const bool zeros = i % columns == columns - 1;
    x[i] = r == 31 ? nan : r >= 29 || zeros ? (r % 2 == 0 ? 0.0 : -0.0) : static_cast<double>(r % 9) - 4.0;
  }
  if (nan_start < columns) x[nan_start] = nan;
  return x;
}

// The same bits, a signed zero's sign included: == would not tell them.
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Against a search written out differently: each column on its own, the
// extreme over the values that are not NaN, then the first row holding it
// (a NaN at the start stays, as nothing compares below or above it).
// Column counts 1, 2 and 7 give the scalar, the paired and both paths (a
// NaN first in a paired column and in the odd one); a single row; one
// scratch reused by every call. Exact, as min and max only select.
TEST(Response, ColumnExtremesAreTheFirstRowOfTheColumnsExtreme) {
  const std::vector<Reduction> which{Reduction::min, Reduction::max, Reduction::argmin_time, Reduction::argmax_time};
  ReductionScratch scratch;
  for (std::size_t T : {std::size_t{1}, std::size_t{60}})
    for (auto [columns, nan_start] : {std::pair<std::size_t, std::size_t>{1, 9}, {2, 1}, {7, 3}, {7, 6}}) {
      SCOPED_TRACE(std::to_string(T) + " rows, " + std::to_string(columns) + " columns");
      const std::vector<double> x = extremes_trajectory(T, columns, nan_start);
      std::vector<double> times(T), out;
      for (std::size_t k = 0; k < T; ++k) times[k] = 0.5 * static_cast<double>(k);
      reduce_columns(x, times, columns, which, out, scratch);
      ASSERT_EQ(out.size(), which.size() * columns);
      for (std::size_t c = 0; c < columns; ++c)
        for (int side = 0; side < 2; ++side) {
          std::vector<double> column;
          for (std::size_t k = 0; k < T; ++k) column.push_back(x[k * columns + c]);
          double best = column[0];
          std::size_t at = 0;
          if (!std::isnan(best)) {
            for (double v : column)
              if (!std::isnan(v)) best = side == 0 ? std::min(best, v) : std::max(best, v);
            while (column[at] != best) ++at;
          }
          SCOPED_TRACE("column " + std::to_string(c) + (side == 0 ? " min" : " max"));
          EXPECT_TRUE(same_bits(out[static_cast<std::size_t>(side) * columns + c], column[at]));
          EXPECT_EQ(out[(2 + static_cast<std::size_t>(side)) * columns + c], times[at]);
        }
    }
}

TEST(Response, LimitStatesAreStrict) {
  Response r = response(Response::Reduce::max);
  r.fail_if = Response::FailIf::above;
  r.limit = 1.0;
  EXPECT_TRUE(r.exceeds(1.5));
  EXPECT_FALSE(r.exceeds(1.0));
  EXPECT_FALSE(r.exceeds(std::numeric_limits<double>::quiet_NaN()));
  EXPECT_TRUE(r.exceeds(kInf));
  r.fail_if = Response::FailIf::below;
  EXPECT_TRUE(r.exceeds(0.5));
  EXPECT_FALSE(r.exceeds(kInf));
}

// The Wilson interval's ends are the two roots p of
//   (k/n - p)^2 = z^2 p (1 - p) / n;
// checked through that quadratic (not the closed form the code uses), to
// 1e-14, and against the familiar special cases.
TEST(Wilson, EndsSolveTheScoreQuadratic) {
  for (auto [k, n] :
       {std::pair{1ULL, 16ULL}, {0ULL, 10ULL}, {10ULL, 10ULL}, {50ULL, 100ULL}, {3ULL, 1000ULL}, {999ULL, 1000ULL}}) {
    SCOPED_TRACE(std::to_string(k) + " of " + std::to_string(n));
    const Interval w = wilson_interval(k, n);
    const double p = static_cast<double>(k) / static_cast<double>(n), z = kZ95;
    for (double end : {w.low, w.high}) {
      const double lhs = (p - end) * (p - end), rhs = z * z * end * (1.0 - end) / static_cast<double>(n);
      EXPECT_NEAR(lhs, rhs, 1e-14);
    }
    EXPECT_LE(w.low, p);
    EXPECT_GE(w.high, p);
  }
  // k = 0: [0, z^2 / (n + z^2)].
  const Interval none = wilson_interval(0, 10);
  EXPECT_EQ(none.low, 0.0);
  EXPECT_NEAR(none.high, kZ95 * kZ95 / (10.0 + kZ95 * kZ95), 1e-15);
  // Symmetric: k of n mirrors n - k of n.
  const Interval a = wilson_interval(3, 40), b = wilson_interval(37, 40);
  EXPECT_NEAR(a.low, 1.0 - b.high, 1e-15);
  EXPECT_NEAR(a.high, 1.0 - b.low, 1e-15);
  // The value the Kapitza example printed for 1 of 16: [0.01112, 0.2833].
  const Interval one = wilson_interval(1, 16);
  EXPECT_NEAR(one.low, 0.01112, 5e-6);
  EXPECT_NEAR(one.high, 0.2833, 5e-5);
}

// Ten samples, two failed; the response is the sample index; limit: above 5.
TEST(Answers, ExceedanceCountsSuccessfulSamplesAndReportsTheFailedOnes) {
  EnsembleSpec spec;
  spec.design = Design::monte_carlo;
  Response r = response(Response::Reduce::max);
  r.fail_if = Response::FailIf::above;
  r.limit = 5.0;
  spec.responses = {r};
  std::vector<std::int32_t> status(10, 0);
  status[7] = 1;
  status[2] = 2;
  std::vector<double> values;
  for (int k = 0; k < 10; ++k) values.push_back(status[k] == 0 ? k : std::nan(""));
  const ensemble::ResponseTable table(status, {}, values, 0, 1);
  const auto answers = answer_responses(spec, table);
  ASSERT_EQ(answers.size(), 1u);
  const ResponseAnswer& a = answers[0];
  EXPECT_EQ(a.used, 8u);
  EXPECT_EQ(a.failed, 2u);
  // 0 1 3 4 5 6 8 9: mean 4.5.
  EXPECT_DOUBLE_EQ(a.mean, 4.5);
  ASSERT_TRUE(a.exceedance);
  EXPECT_EQ(a.exceedance->exceeded, 3u);  // 6, 8, 9
  EXPECT_EQ(a.exceedance->successful, 8u);
  EXPECT_EQ(a.exceedance->failed, 2u);
  EXPECT_DOUBLE_EQ(a.exceedance->probability, 3.0 / 8.0);
  // Convergence at 1, 2, 4, 8 and 10 samples.
  std::vector<std::uint64_t> counts, used;
  for (const auto& p : a.convergence) counts.push_back(p.samples), used.push_back(p.used);
  EXPECT_EQ(counts, (std::vector<std::uint64_t>{1, 2, 4, 8, 10}));
  EXPECT_EQ(used, (std::vector<std::uint64_t>{1, 2, 3, 6, 8}));
  EXPECT_DOUBLE_EQ(a.convergence[3].probability, 1.0 / 6.0);  // of 0 1 3 4 5 6: just 6
  EXPECT_TRUE(std::isnan(a.convergence[0].sem));              // one value: no spread
}

TEST(Answers, InfiniteValuesAreCountedNotAveraged) {
  EnsembleSpec spec;
  spec.responses = {response(Response::Reduce::first_time_above, 1.0)};
  const ensemble::ResponseTable table({0, 0, 0, 0}, {}, {1.0, kInf, 3.0, kInf}, 0, 1);
  const ResponseAnswer a = answer_responses(spec, table).at(0);
  EXPECT_EQ(a.used, 2u);
  EXPECT_EQ(a.not_finite, 2u);
  EXPECT_EQ(a.mean, 2.0);
  EXPECT_FALSE(a.exceedance);
}

// Saltelli's rows: A_j, B_j, then AB_i,j = A_j with input i from B_j; and a
// base point j does not depend on N (prefixes of whole blocks are nested).
TEST(SaltelliDesign, BlocksHoldABAndTheMixedRows) {
  constexpr unsigned D = 4;
  const SampleDesign small(Design::saltelli, 9, 8 * (D + 2), D), large(Design::saltelli, 9, 64 * (D + 2), D);
  for (std::uint64_t j : {0u, 1u, 5u}) {
    std::vector<double> a(D), b(D), ab(D), again(D);
    small.point(j * (D + 2), a);
    small.point(j * (D + 2) + 1, b);
    large.point(j * (D + 2), again);
    EXPECT_EQ(a, again);
    for (unsigned d = 0; d < D; ++d) EXPECT_NE(a[d], b[d]);
    for (unsigned i = 0; i < D; ++i) {
      small.point(j * (D + 2) + 2 + i, ab);
      for (unsigned d = 0; d < D; ++d) EXPECT_EQ(ab[d], d == i ? b[d] : a[d]) << "j " << j << " i " << i;
      EXPECT_EQ(saltelli_place(j * (D + 2) + 2 + i, D).role, SaltelliRole::ab);
      EXPECT_EQ(saltelli_place(j * (D + 2) + 2 + i, D).unit, i);
    }
    for (unsigned d = 0; d < D; ++d) EXPECT_EQ(small.uniform(j * (D + 2) + 1, d), b[d]);
  }
}

// With groups ([[ensemble.group]]): 5 inputs in 3 units {0, 3}, {1}, {2, 4}
// make blocks of 3 + 2 runs; A and B are the ungrouped design's (same 2D
// Sobol dimensions) and AB_g takes exactly unit g's inputs from B.
TEST(SaltelliDesign, GroupedBlocksTakeAWholeGroupFromB) {
  constexpr unsigned D = 5, U = 3;
  const std::vector<unsigned> unit = {0, 1, 2, 0, 2};
  const SampleDesign grouped(Design::saltelli, 9, 8 * (U + 2), D, unit), plain(Design::saltelli, 9, 8 * (D + 2), D);
  for (std::uint64_t j : {0u, 3u, 7u}) {
    std::vector<double> a(D), b(D), ab(D), plain_a(D), plain_b(D);
    grouped.point(j * (U + 2), a);
    grouped.point(j * (U + 2) + 1, b);
    plain.point(j * (D + 2), plain_a);
    plain.point(j * (D + 2) + 1, plain_b);
    EXPECT_EQ(a, plain_a);
    EXPECT_EQ(b, plain_b);
    for (unsigned g = 0; g < U; ++g) {
      grouped.point(j * (U + 2) + 2 + g, ab);
      for (unsigned d = 0; d < D; ++d) EXPECT_EQ(ab[d], unit[d] == g ? b[d] : a[d]) << "j " << j << " g " << g;
      EXPECT_EQ(saltelli_place(j * (U + 2) + 2 + g, U).unit, g);
    }
  }
}

}  // namespace
