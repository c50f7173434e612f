#include "ensemble/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace treedyn::ensemble {

Calibration calibrate(std::span<const double> nominal, std::span<const double> lo,
                      std::span<const double> hi, std::span<const double> column_scale,
                      std::size_t columns, int bins) {
  Calibration c;
  const std::size_t n = nominal.size();
  c.center.assign(nominal.begin(), nominal.end());
  c.scale.resize(n);
  c.low.resize(n);
  c.width.resize(n);
  for (std::size_t e = 0; e < n; ++e) {
    // Fallback unit when the pilot saw no spread: 2^-10 of the column's size,
    // so spreads up to 2^10 times the column's size remain representable.
    // A column that is zero all along the nominal run (a spring energy with
    // no springs, say) falls back to one unit of the quantity.
    const double column = column_scale[e % columns] > 0.0 ? column_scale[e % columns] : 1.0;
    const double fallback = std::ldexp(column, -10);
    const bool seen = std::isfinite(lo[e]) && std::isfinite(hi[e]);
    const double spread = seen ? hi[e] - lo[e] : 0.0;
    const double largest = seen ? std::max(std::abs(lo[e]), std::abs(hi[e])) : 0.0;
    c.scale[e] = largest > 0.0 ? largest : fallback;
    // Histogram: the pilot's range widened by a quarter of its spread each side.
    double low = nominal[e] + (seen ? lo[e] : 0.0);
    double high = nominal[e] + (seen ? hi[e] : 0.0);
    const double margin = spread > 0.0 ? 0.25 * spread : c.scale[e];
    low -= margin;
    high += margin;
    c.low[e] = low;
    c.width[e] = (high - low) / bins;
    if (!(c.width[e] > 0.0)) c.width[e] = std::max(std::abs(low), 1.0) * 1e-12;
  }
  return c;
}

EnsembleStatistics::EnsembleStatistics(std::size_t times, std::size_t columns, int bins,
                                       Calibration calibration)
    : times_(times), columns_(columns), bins_(bins), calibration_(std::move(calibration)) {
  const std::size_t n = entries();
  if (calibration_.center.size() != n) throw std::invalid_argument("calibration size mismatch");
  sum_.assign(n, 0);
  square_sum_.assign(n, 0);
  min_.assign(n, std::numeric_limits<double>::infinity());
  max_.assign(n, -std::numeric_limits<double>::infinity());
  counts_.assign(n * static_cast<std::size_t>(bins + 2), 0);
  out_of_range_.assign(n, 0);
}

void EnsembleStatistics::add_sample(std::span<const double> trajectory) {
  const std::size_t n = entries();
  if (trajectory.size() != n) throw std::invalid_argument("trajectory size mismatch");
  for (std::size_t e = 0; e < n; ++e) {
    // + 0.0 turns -0.0 into +0.0: min and max of signed zeros would otherwise
    // depend on which zero came first.
    const double x = trajectory[e] + 0.0;
    if (!std::isfinite(x)) {  // never from a successful run; kept out of everything
      ++out_of_range_[e];
      continue;
    }
    min_[e] = std::min(min_[e], x);
    max_[e] = std::max(max_[e], x);
    const double scaled = (x - calibration_.center[e]) / calibration_.scale[e];
    if (std::abs(scaled) <= kMaxScaledDeviation) {
      // Rounded to the nearest unit of the fixed point: unbiased.
      sum_[e] += static_cast<wide>(std::nearbyint(std::ldexp(scaled, kSumBits)));
      square_sum_[e] += static_cast<wide>(std::nearbyint(std::ldexp(scaled * scaled, kSquareBits)));
    } else {
      ++out_of_range_[e];
    }
    const double position = (x - calibration_.low[e]) / calibration_.width[e];
    int bin;
    if (position < 0.0)
      bin = 0;
    else if (position >= bins_)
      bin = bins_ + 1;
    else
      bin = 1 + static_cast<int>(position);
    ++counts_[e * static_cast<std::size_t>(bins_ + 2) + static_cast<std::size_t>(bin)];
  }
  ++samples_;
}

void EnsembleStatistics::merge(const EnsembleStatistics& o) {
  for (std::size_t e = 0; e < entries(); ++e) {
    sum_[e] += o.sum_[e];
    square_sum_[e] += o.square_sum_[e];
    min_[e] = std::min(min_[e], o.min_[e]);
    max_[e] = std::max(max_[e], o.max_[e]);
    out_of_range_[e] += o.out_of_range_[e];
  }
  for (std::size_t k = 0; k < counts_.size(); ++k) counts_[k] += o.counts_[k];
  samples_ += o.samples_;
}

std::uint64_t EnsembleStatistics::count(std::size_t e) const { return samples_ - out_of_range_[e]; }

double EnsembleStatistics::mean(std::size_t e) const {
  const std::uint64_t n = count(e);
  if (n == 0) return std::numeric_limits<double>::quiet_NaN();
  const long double mean_scaled =
      std::ldexp(static_cast<long double>(sum_[e]), -kSumBits) / static_cast<long double>(n);
  return static_cast<double>(calibration_.center[e] + calibration_.scale[e] * mean_scaled);
}

double EnsembleStatistics::std_dev(std::size_t e) const {
  const std::uint64_t n = count(e);
  if (n < 2) return std::numeric_limits<double>::quiet_NaN();
  const long double s1 = std::ldexp(static_cast<long double>(sum_[e]), -kSumBits);
  const long double s2 = std::ldexp(static_cast<long double>(square_sum_[e]), -kSquareBits);
  const long double nn = static_cast<long double>(n);
  const long double variance = std::max<long double>(0.0L, (s2 - s1 * s1 / nn) / (nn - 1.0L));
  return static_cast<double>(calibration_.scale[e] * std::sqrt(variance));
}

std::span<const std::uint32_t> EnsembleStatistics::histogram(std::size_t e) const {
  const auto stride = static_cast<std::size_t>(bins_ + 2);
  return {counts_.data() + e * stride, stride};
}

double EnsembleStatistics::bin_edge(std::size_t e, int edge) const {
  return calibration_.low[e] + edge * calibration_.width[e];
}

double EnsembleStatistics::quantile(std::size_t e, double q) const {
  const auto h = histogram(e);
  std::uint64_t total = 0;
  for (std::uint32_t c : h) total += c;
  if (total == 0) return std::numeric_limits<double>::quiet_NaN();
  const double target = q * static_cast<double>(total);
  double below = 0.0;
  for (int b = 0; b < bins_ + 2; ++b) {
    const double c = h[static_cast<std::size_t>(b)];
    if (c > 0.0 && below + c >= target) {
      // The segment this count covers: [min, low) for underflow, (high, max]
      // for overflow, the bin otherwise; linear inside it.
      double left, right;
      if (b == 0) {
        left = min_[e];
        right = bin_edge(e, 0);
      } else if (b == bins_ + 1) {
        left = bin_edge(e, bins_);
        right = max_[e];
      } else {
        left = bin_edge(e, b - 1);
        right = bin_edge(e, b);
      }
      const double x = left + (right - left) * (target - below) / c;
      return std::clamp(x, min_[e], max_[e]);
    }
    below += c;
  }
  return max_[e];
}

}  // namespace treedyn::ensemble
