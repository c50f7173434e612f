#include "sampling/distribution.hpp"

#include <boost/math/distributions/lognormal.hpp>
#include <boost/math/distributions/normal.hpp>

#include <sstream>

namespace treedyn::sampling {

double Distribution::quantile(double u) const {
  switch (kind) {
    case Kind::normal:
      return boost::math::quantile(boost::math::normal(mean, std), u);
    case Kind::truncated_normal: {
      // Invert on the side of the mean the interval lies on, with upper-tail
      // probabilities above the mean, so tail intervals keep their digits.
      const boost::math::normal n(mean, std);
      double x;
      if (lower > mean) {
        const double sa = boost::math::cdf(boost::math::complement(n, lower));
        const double sb = boost::math::cdf(boost::math::complement(n, upper));
        const double q = sa - u * (sa - sb);
        x = q > 0.0 ? boost::math::quantile(boost::math::complement(n, q)) : upper;
      } else {
        const double a = boost::math::cdf(n, lower), b = boost::math::cdf(n, upper);
        const double p = a + u * (b - a);
        x = p <= 0.0 ? lower : p >= 1.0 ? upper : boost::math::quantile(n, p);
      }
      return std::min(std::max(x, lower), upper);
    }
    case Kind::uniform:
      return lower + u * (upper - lower);
    case Kind::lognormal:
      return boost::math::quantile(boost::math::lognormal(mu, sigma), u);
  }
  return 0.0;
}

double Distribution::cdf(double x) const {
  switch (kind) {
    case Kind::normal:
      return boost::math::cdf(boost::math::normal(mean, std), x);
    case Kind::truncated_normal: {
      if (x <= lower) return 0.0;
      if (x >= upper) return 1.0;
      const boost::math::normal n(mean, std);
      if (lower > mean) {  // upper-tail probabilities, as in quantile()
        const double sa = boost::math::cdf(boost::math::complement(n, lower));
        const double sb = boost::math::cdf(boost::math::complement(n, upper));
        return (sa - boost::math::cdf(boost::math::complement(n, x))) / (sa - sb);
      }
      const double a = boost::math::cdf(n, lower), b = boost::math::cdf(n, upper);
      return (boost::math::cdf(n, x) - a) / (b - a);
    }
    case Kind::uniform:
      return x <= lower ? 0.0 : x >= upper ? 1.0 : (x - lower) / (upper - lower);
    case Kind::lognormal:
      return x <= 0.0 ? 0.0 : boost::math::cdf(boost::math::lognormal(mu, sigma), x);
  }
  return 0.0;
}

std::string Distribution::describe() const {
  std::ostringstream s;
  s << name(kind) << "(";
  switch (kind) {
    case Kind::normal:
      s << "mean=" << mean << ", std=" << std;
      break;
    case Kind::truncated_normal:
      s << "mean=" << mean << ", std=" << std << ", lower=" << lower << ", upper=" << upper;
      break;
    case Kind::uniform:
      s << "lower=" << lower << ", upper=" << upper;
      break;
    case Kind::lognormal:
      s << "mu=" << mu << ", sigma=" << sigma;
      break;
  }
  s << ")";
  return s.str();
}

}  // namespace treedyn::sampling
