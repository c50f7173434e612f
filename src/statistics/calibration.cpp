#include "statistics/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/hash.hpp"

namespace treedyn::statistics {

void Calibration::write(ByteWriter& out) const {
  for (const auto* v : {&center, &scale, &low, &width}) out.put_vector(*v);
}

Calibration Calibration::read(ByteReader& in, std::size_t entries) {
  Calibration c;
  for (auto* v : {&c.center, &c.scale, &c.low, &c.width}) {
    *v = in.get_vector<double>();
    if (v->size() != entries) in.fail("a calibration of another shape");
  }
  if (!c.usable()) in.fail("its calibration is not usable");
  return c;
}

bool Calibration::usable() const {
  const std::size_t n = center.size();
  if (scale.size() != n || low.size() != n || width.size() != n) return false;
  for (std::size_t e = 0; e < n; ++e)
    if (!std::isfinite(center[e]) || !std::isfinite(low[e]) || !(scale[e] > 0.0) || !std::isfinite(scale[e]) ||
        !(width[e] > 0.0) || !std::isfinite(width[e]))
      return false;
  return true;
}

std::uint64_t Calibration::hash() const {
  std::vector<char> bytes;
  ByteWriter out(bytes);
  write(out);
  return hash64(bytes);
}

std::vector<double> column_scales(std::span<const double> nominal, std::size_t columns) {
  std::vector<double> scale(columns, 0.0);
  for (std::size_t e = 0; e < nominal.size(); ++e)
    scale[e % columns] = std::max(scale[e % columns], std::abs(nominal[e]));
  return scale;
}

Calibration calibrate(std::span<const double> nominal, std::span<const double> lo, std::span<const double> hi,
                      std::span<const double> column_scale, std::size_t columns, int bins) {
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
    if (!std::isfinite(low) || !std::isfinite(c.width[e])) {
      // A pilot spread near the largest double: the range overflowed. The
      // histogram then spans every double (finite edges), so that no
      // position (x - low) / width is NaN.
      constexpr double largest_double = std::numeric_limits<double>::max();
      c.low[e] = -largest_double;
      c.width[e] = largest_double / bins * 2.0;
    }
    if (!(c.width[e] > 0.0)) c.width[e] = std::max(std::abs(low), 1.0) * 1e-12;
  }
  return c;
}

}  // namespace treedyn::statistics
