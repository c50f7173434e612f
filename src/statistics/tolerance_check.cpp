#include "statistics/tolerance_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace treedyn::statistics {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string number(double v, const char* format = "%.3g") {
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
}

// Standard deviation (n - 1) of column r's finite values, in row order.
double spread_of(const std::vector<double>& rows, std::size_t responses, std::size_t r) {
  double n = 0.0, mean = 0.0, m2 = 0.0;  // Welford
  for (std::size_t k = r; k < rows.size(); k += responses) {
    if (!std::isfinite(rows[k])) continue;
    n += 1.0;
    const double delta = rows[k] - mean;
    mean += delta / n;
    m2 += delta * (rows[k] - mean);
  }
  return n > 1.0 ? std::sqrt(m2 / (n - 1.0)) : kNaN;
}

}  // namespace

void ToleranceCheck::write(ByteWriter& out) const {
  out.put(rtol);
  out.put(atol);
  out.put_vector(samples);
  out.put_vector(change);
  out.put_vector(spread);
}

ToleranceCheck ToleranceCheck::read(ByteReader& in) {
  ToleranceCheck c;
  c.rtol = in.get<double>();
  c.atol = in.get<double>();
  c.samples = in.get_vector<std::uint64_t>();
  c.change = in.get_vector<double>();
  c.spread = in.get_vector<double>();
  if (c.change.size() != c.spread.size()) in.fail("tolerance check of two sizes");
  return c;
}

ToleranceCheck check_tolerances(double rtol, double atol, std::size_t responses, const std::vector<double>& pilot,
                                const std::vector<double>& rerun) {
  ToleranceCheck c;
  c.rtol = rtol, c.atol = atol;
  if (responses == 0) return c;
  c.change.assign(responses, 0.0);
  for (std::size_t k = 0; k * responses < rerun.size() && (k + 1) * responses <= pilot.size(); ++k) {
    bool both = true;  // a failed run (NaN) at either tolerance says nothing of the error
    for (std::size_t r = 0; r < responses; ++r)
      both = both && !std::isnan(pilot[k * responses + r]) && !std::isnan(rerun[k * responses + r]);
    if (!both) continue;
    c.samples.push_back(k);
    for (std::size_t r = 0; r < responses; ++r) {
      const double a = pilot[k * responses + r], b = rerun[k * responses + r];
      // Equal infinities (a level never crossed at either tolerance) agree.
      const double d = a == b ? 0.0 : std::abs(a - b);
      c.change[r] = std::max(c.change[r], std::isnan(d) ? std::numeric_limits<double>::infinity() : d);
    }
  }
  if (c.samples.empty()) c.change.assign(responses, kNaN);
  for (std::size_t r = 0; r < responses; ++r) c.spread.push_back(spread_of(pilot, responses, r));
  return c;
}

ToleranceVerdict tolerance_verdict(const ToleranceCheck& check, std::size_t r) {
  ToleranceVerdict v;
  v.ratio = check.change[r] / check.spread[r];
  if (!std::isfinite(v.ratio) || !(check.spread[r] > 0.0)) return v;
  v.kind = v.ratio > kTooLoose     ? ToleranceVerdict::Kind::too_loose
           : v.ratio < kFarTighter ? ToleranceVerdict::Kind::far_tighter
                                   : ToleranceVerdict::Kind::enough;
  // A change of 0 (identical to the last digit) says nothing of how far the
  // tolerances could go: the furthest step offered.
  const double wanted = v.ratio > 0.0 ? kToleranceTarget / v.ratio : 100.0;
  v.factor = std::pow(10.0, std::floor(std::log10(std::clamp(wanted, 1e-4, 100.0)) + 1e-9));
  return v;
}

std::string describe_verdict(const ToleranceCheck& check, std::size_t r) {
  const ToleranceVerdict v = tolerance_verdict(check, r);
  const std::string tolerances =
      "rtol = " + number(check.rtol * v.factor, "%.0e") + ", atol = " + number(check.atol * v.factor, "%.0e");
  const std::string ratio = "its change at 100x tighter tolerances is " + number(v.ratio, "%.2g") + " of its spread";
  switch (v.kind) {
    case ToleranceVerdict::Kind::too_loose:
      return "too loose for this answer: " + ratio + "; tighten [integrator] to " + tolerances + " (about " +
             number(kToleranceTarget, "%.2g") + " of the spread if the error follows the tolerances)";
    case ToleranceVerdict::Kind::far_tighter:
      return "far tighter than this answer needs: " + ratio + "; try " + tolerances + " (" + number(v.factor, "%.0f") +
             "x looser, for fewer steps; this check then says whether it holds)";
    case ToleranceVerdict::Kind::enough:
      return "enough: " + ratio;
    case ToleranceVerdict::Kind::unknown:
      break;
  }
  if (check.samples.empty()) return "not checked: no pilot sample succeeded at both tolerances";
  return "not checked: the response has no spread over the pilot (" + ratio + ")";
}

}  // namespace treedyn::statistics
