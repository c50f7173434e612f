// Distributions of perturbed inputs, applied to a design's uniform u by the
// inverse distribution function (Boost.Math), so Latin-hypercube strata and
// Sobol points keep their structure.
#pragma once

#include <string>
#include <string_view>

#include "common/enum_names.hpp"

namespace treedyn::sampling {

struct Distribution {
  enum class Kind { normal, truncated_normal, uniform, lognormal } kind = Kind::normal;
  double mean = 0.0;   // normal, truncated_normal: of the untruncated normal
  double std = 1.0;    // normal, truncated_normal: > 0
  double lower = 0.0;  // truncated_normal, uniform
  double upper = 1.0;  // truncated_normal, uniform: lower < upper
  double mu = 0.0;     // lognormal: mean of log(x)
  double sigma = 1.0;  // lognormal: std of log(x), > 0

  // x = F^-1(u), u in (0, 1).
  double quantile(double u) const;
  double cdf(double x) const;
  std::string describe() const;
};

inline constexpr NameTable<Distribution::Kind, 4> kDistributionNames{
    {{Distribution::Kind::normal, "normal"},
     {Distribution::Kind::truncated_normal, "truncated_normal"},
     {Distribution::Kind::uniform, "uniform"},
     {Distribution::Kind::lognormal, "lognormal"}}};
inline std::string_view name(Distribution::Kind k) { return name_in(kDistributionNames, k); }
inline bool parse_distribution(std::string_view text, Distribution::Kind& out) {
  return parse_in(kDistributionNames, text, out);
}

}  // namespace treedyn::sampling
