// The reference values of the ensemble statistics, fixed by the pilot
// samples and identical on every rank: per entry (one output time, one
// column) the centre c (the nominal run's value), the fixed-point unit S of
// the exact sums, and the histogram's range.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "common/bytes.hpp"

namespace treedyn::statistics {

struct Calibration {
  std::vector<double> center;  // c: nominal value
  std::vector<double> scale;   // S > 0: fixed-point unit
  std::vector<double> low;     // histogram range [low, low + bins * width)
  std::vector<double> width;   // bin width > 0

  std::size_t entries() const { return center.size(); }
  bool operator==(const Calibration&) const = default;
  void write(ByteWriter& out) const;
  // Reads one written by write() and checks it (usable). Throws DecodeError.
  static Calibration read(ByteReader& in, std::size_t entries);
  // The same number of each, all finite, scales and widths positive: then a
  // finite value's histogram position (x - low) / width is never NaN.
  bool usable() const;
  // Names this calibration in a statistics state (to refuse adding states
  // of different calibrations).
  std::uint64_t hash() const;
};

// Builds the calibration from the nominal trajectory and the deviations seen
// in the pilot samples (per entry min and max of x - c; +inf/-inf if none).
// `column_scale` is each column's largest |nominal| over time (fallback unit).
Calibration calibrate(std::span<const double> nominal, std::span<const double> pilot_min_deviation,
                      std::span<const double> pilot_max_deviation, std::span<const double> column_scale,
                      std::size_t columns, int bins);

// Per-column largest |nominal| over time: the fallback fixed-point unit.
std::vector<double> column_scales(std::span<const double> nominal, std::size_t columns);

}  // namespace treedyn::statistics
