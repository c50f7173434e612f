// Is the integration accurate enough for the answers? The pilot's first
// samples are run again with the job's rtol and atol 100 times tighter; the
// largest change of each response, against its spread over the pilot
// (the standard deviation the answers are about), says whether the
// tolerances are too loose for the answer (a change above a tenth of the
// spread) or far tighter than it needs (one below a thousandth), and what
// tolerance would do.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/bytes.hpp"

namespace treedyn::statistics {

inline constexpr double kToleranceFactor = 0.01;      // the rerun's rtol and atol over the job's
inline constexpr std::uint64_t kToleranceReruns = 4;  // pilot samples 0 .. 3
inline constexpr double kTooLoose = 0.1;              // change / spread above this: too loose
inline constexpr double kFarTighter = 1e-3;           // ... below this: far tighter than needed
inline constexpr double kToleranceTarget = 0.01;      // what a suggested tolerance aims at

struct ToleranceCheck {
  double rtol = 0.0, atol = 0.0;       // the job's
  std::vector<std::uint64_t> samples;  // rerun, and successful at both tolerances
  // Per response: the largest |y(tight) - y| over those samples, and the
  // standard deviation (n - 1) of y over the pilot's successful samples with
  // finite values (NaN with fewer than two).
  std::vector<double> change, spread;

  bool empty() const { return change.empty(); }
  void write(ByteWriter& out) const;
  static ToleranceCheck read(ByteReader& in);
};

// From the pilot's responses (pilot samples x R, row-major; a failed sample
// NaN) and those of the samples rerun (kToleranceReruns x R at most; a
// failed rerun NaN), sample k's rerun in row k.
ToleranceCheck check_tolerances(double rtol, double atol, std::size_t responses, const std::vector<double>& pilot,
                                const std::vector<double>& rerun);

struct ToleranceVerdict {
  enum class Kind { unknown, too_loose, enough, far_tighter } kind = Kind::unknown;
  double ratio = 0.0;   // change / spread
  double factor = 1.0;  // the tolerances times this would bring the ratio to kToleranceTarget
                        // (the error taken as proportional to them), a power of ten in [1e-4, 100]
};
ToleranceVerdict tolerance_verdict(const ToleranceCheck& check, std::size_t response);

// One line on response r, e.g. "far tighter than this answer needs: its
// change is 9e-06 of its spread; rtol = 1e-06, atol = 1e-08 would do (100x
// looser; check again there)".
std::string describe_verdict(const ToleranceCheck& check, std::size_t response);

}  // namespace treedyn::statistics
