#include "statistics/ensemble_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace treedyn::statistics {
namespace {

constexpr std::uint64_t kStateMagic = 0x3130415453445454ull;  // "TTDSTA01"
enum class CountsLayout : std::uint8_t { dense = 0, sparse = 1 };

// The counts of one piece: dense, or (offset, count) pairs of the non-zero
// ones when that is shorter (a histogram holds few samples in most bins).
void write_counts(std::span<const std::uint32_t> counts, ByteWriter& out) {
  const auto nonzero =
      static_cast<std::size_t>(std::count_if(counts.begin(), counts.end(), [](auto c) { return c != 0; }));
  if (2 * nonzero >= counts.size()) {
    out.put(CountsLayout::dense);
    out.put_vector(counts);
    return;
  }
  out.put(CountsLayout::sparse);
  out.put(static_cast<std::uint64_t>(nonzero));
  for (std::size_t k = 0; k < counts.size(); ++k)
    if (counts[k] != 0) {
      out.put(static_cast<std::uint32_t>(k));
      out.put(counts[k]);
    }
}

void add_counts(std::span<std::uint32_t> counts, ByteReader& in) {
  const auto layout = in.get<CountsLayout>();
  if (layout == CountsLayout::dense) {
    const auto dense = in.get_vector<std::uint32_t>();
    if (dense.size() != counts.size()) in.fail("histogram counts of another shape");
    for (std::size_t k = 0; k < counts.size(); ++k) counts[k] += dense[k];
    return;
  }
  if (layout != CountsLayout::sparse) in.fail("an unknown histogram layout");
  const auto nonzero = in.get<std::uint64_t>();
  if (nonzero > counts.size()) in.fail("more histogram counts than bins");
  for (std::uint64_t k = 0; k < nonzero; ++k) {
    const auto at = in.get<std::uint32_t>();
    const auto count = in.get<std::uint32_t>();
    if (at >= counts.size()) in.fail("a histogram count outside its bins");
    counts[at] += count;
  }
}

// Element-wise sum, min or max of a vector read from `in` into `into`.
template <class T, class Combine>
void add_vector(std::span<T> into, ByteReader& in, Combine combine) {
  const std::vector<T> other = in.get_vector<T>();
  if (other.size() != into.size()) in.fail("statistics of another shape");
  for (std::size_t k = 0; k < into.size(); ++k) into[k] = combine(into[k], other[k]);
}

}  // namespace

namespace {
// Samples per block: kMaxBlock, fewer when the block would pass 16 MiB.
std::size_t block_for(std::size_t entries) {
  return std::clamp<std::size_t>((std::size_t{1} << 21) / std::max<std::size_t>(entries, 1), 1,
                                 EnsembleStatistics::kMaxBlock);
}
}  // namespace

EnsembleStatistics::EnsembleStatistics(std::size_t times, std::size_t columns, int bins, Calibration calibration)
    : times_(times), columns_(columns), bins_(bins), calibration_(std::move(calibration)) {
  const std::size_t n = entries();
  if (calibration_.center.size() != n) throw std::invalid_argument("calibration size mismatch");
  // The fold's bins need finite edges and positive widths (block_fold.hpp).
  if (!calibration_.usable()) throw std::invalid_argument("a calibration that is not usable");
  block_ = block_for(n);
  sum_.assign(n, 0);
  square_sum_.assign(n, 0);
  min_.assign(n, std::numeric_limits<double>::infinity());
  max_.assign(n, -std::numeric_limits<double>::infinity());
  counts_.assign(n * static_cast<std::size_t>(bins + 2), 0);
  out_of_range_.assign(n, 0);
  rows_.assign(block_, std::vector<double>(n, 0.0));
}

double EnsembleStatistics::memory_bytes(double entries, int bins) {
  // uint32 bin counters (bins + under/overflow), two 128-bit sums, min, max,
  // an out-of-range count, the calibration (4 doubles) and a block of
  // pending samples.
  const double block = static_cast<double>(block_for(static_cast<std::size_t>(std::max(entries, 1.0))));
  return entries * (4.0 * (bins + 2) + 2 * 16.0 + 3 * 8.0 + 4 * 8.0 + 8.0 * block);
}

void EnsembleStatistics::add_sample(std::span<const double> trajectory) {
  const std::size_t n = entries();
  if (trajectory.size() != n) throw std::invalid_argument("trajectory size mismatch");
  std::copy(trajectory.begin(), trajectory.end(), rows_[pending_samples_].begin());
  ++pending_samples_;
  ++samples_;
  if (pending_samples_ == block_) fold_pending();
}

void EnsembleStatistics::take_sample(std::vector<double>& trajectory) {
  if (trajectory.size() != entries()) throw std::invalid_argument("trajectory size mismatch");
  rows_[pending_samples_].swap(trajectory);
  ++pending_samples_;
  ++samples_;
  if (pending_samples_ == block_) fold_pending();
}

void EnsembleStatistics::use_fold_lanes(int lanes) {
  if (!runs_fold_lanes(lanes))
    throw std::invalid_argument("this CPU does not fold " + std::to_string(lanes) + " lanes");
  lanes_ = lanes;
}

// The pending block, entry by entry (block_fold.hpp).
void EnsembleStatistics::fold_pending() const {
  if (pending_samples_ == 0) return;
  const FoldBlock block{rows_.data(),
                        entries(),
                        pending_samples_,
                        calibration_.center.data(),
                        calibration_.scale.data(),
                        calibration_.low.data(),
                        calibration_.width.data(),
                        bins_};
  const FoldTotals totals{sum_.data(), square_sum_.data(), min_.data(),
                          max_.data(), counts_.data(),     out_of_range_.data()};
  fold_block(block, totals, lanes_);
  pending_samples_ = 0;
}

void EnsembleStatistics::merge(const EnsembleStatistics& o) {
  if (o.entries() != entries() || o.bins_ != bins_ || !(o.calibration_ == calibration_))
    throw std::invalid_argument("merging statistics of another shape or calibration");
  fold_pending();
  o.fold_pending();
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

namespace {
// Entries per piece: 4096, fewer when the bins would make a piece large.
std::size_t entries_per_piece(int bins) {
  return std::clamp<std::size_t>((std::size_t{1} << 24) / static_cast<std::size_t>(bins + 2), 1, 4096);
}
}  // namespace

std::size_t EnsembleStatistics::state_pieces() const {
  const std::size_t per = entries_per_piece(bins_);
  return 1 + (entries() + per - 1) / per;
}

void EnsembleStatistics::write_state_piece(std::size_t piece, ByteWriter& out) const {
  fold_pending();
  if (piece == 0) {
    out.put(kStateMagic);
    out.put(static_cast<std::uint64_t>(entries()));
    out.put(static_cast<std::int64_t>(bins_));
    out.put(calibration_.hash());
    out.put(samples_);
    return;
  }
  const std::size_t per = entries_per_piece(bins_);
  const std::size_t first = (piece - 1) * per, end = std::min(entries(), first + per);
  if (first >= end) throw std::out_of_range("no such statistics piece");
  const std::size_t n = end - first, stride = counters_per_entry();
  out.put_vector(std::span<const wide>(sum_).subspan(first, n));
  out.put_vector(std::span<const wide>(square_sum_).subspan(first, n));
  out.put_vector(std::span<const double>(min_).subspan(first, n));
  out.put_vector(std::span<const double>(max_).subspan(first, n));
  out.put_vector(std::span<const std::uint64_t>(out_of_range_).subspan(first, n));
  write_counts(std::span<const std::uint32_t>(counts_).subspan(first * stride, n * stride), out);
}

void EnsembleStatistics::add_state_piece(std::size_t piece, ByteReader& in) {
  if (piece == 0) {
    if (in.get<std::uint64_t>() != kStateMagic) in.fail("not a statistics state");
    if (in.get<std::uint64_t>() != entries() || in.get<std::int64_t>() != bins_) in.fail("statistics of another shape");
    if (in.get<std::uint64_t>() != calibration_.hash()) in.fail("statistics of another calibration");
    samples_ += in.get<std::uint64_t>();
    return;
  }
  const std::size_t per = entries_per_piece(bins_);
  const std::size_t first = (piece - 1) * per, end = std::min(entries(), first + per);
  if (first >= end) in.fail("a statistics piece beyond its entries");
  const std::size_t n = end - first, stride = counters_per_entry();
  const auto sum = [](auto a, auto b) { return a + b; };
  add_vector(std::span<wide>(sum_).subspan(first, n), in, sum);
  add_vector(std::span<wide>(square_sum_).subspan(first, n), in, sum);
  add_vector(std::span<double>(min_).subspan(first, n), in, [](double a, double b) { return std::min(a, b); });
  add_vector(std::span<double>(max_).subspan(first, n), in, [](double a, double b) { return std::max(a, b); });
  add_vector(std::span<std::uint64_t>(out_of_range_).subspan(first, n), in, sum);
  add_counts(std::span<std::uint32_t>(counts_).subspan(first * stride, n * stride), in);
}

std::vector<char> EnsembleStatistics::state() const {
  std::vector<char> bytes;
  ByteWriter out(bytes);
  for (std::size_t piece = 0; piece < state_pieces(); ++piece) write_state_piece(piece, out);
  return bytes;
}

void EnsembleStatistics::add_state(std::span<const char> bytes, const std::string& what) {
  ByteReader in(bytes, what);
  for (std::size_t piece = 0; piece < state_pieces(); ++piece) add_state_piece(piece, in);
  if (!in.done()) in.fail("bytes after the statistics");
}

std::uint64_t EnsembleStatistics::count(std::size_t e) const { return samples_ - out_of_range(e); }
std::uint64_t EnsembleStatistics::out_of_range(std::size_t e) const {
  fold_pending();
  return out_of_range_[e];
}
double EnsembleStatistics::min(std::size_t e) const {
  fold_pending();
  return min_[e];
}
double EnsembleStatistics::max(std::size_t e) const {
  fold_pending();
  return max_[e];
}

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
  fold_pending();
  const auto stride = counters_per_entry();
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

}  // namespace treedyn::statistics
