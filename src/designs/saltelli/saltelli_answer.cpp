#include "designs/saltelli/saltelli_answer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ensemble/response_table.hpp"

namespace treedyn::designs {
namespace {

// Indices per Saltelli unit (an input, or a group of them), from the
// complete blocks among the first `base_points`: a block counts only when
// all its U + 2 runs succeeded with finite values.
SobolIndices sobol_of(const EnsembleSpec& spec, const ensemble::ResponseTable& table, std::size_t r,
                      std::uint64_t base_points) {
  const std::size_t d = spec.unit_count(), block = spec.saltelli_block();
  std::vector<double> f_a, f_b, f_ab;
  for (std::uint64_t j = 0; j < base_points; ++j) {
    bool complete = true;
    for (std::size_t m = 0; m < block; ++m) {
      const std::uint64_t k = j * block + m;
      complete = complete && table.ok(k) && std::isfinite(table.response(k, r));
    }
    if (!complete) continue;
    f_a.push_back(table.response(j * block, r));
    f_b.push_back(table.response(j * block + 1, r));
    for (std::size_t i = 0; i < d; ++i) f_ab.push_back(table.response(j * block + 2 + i, r));
  }
  return saltelli_indices(f_a, f_b, f_ab, d, spec.bootstrap_resamples, spec.seed);
}

}  // namespace

// The indices, and their convergence on the first 4, 8, ... base points
// (a prefix of whole blocks is a Saltelli design of its own).
std::shared_ptr<const SaltelliAnswer> answer_saltelli(const EnsembleSpec& spec, const ensemble::ResponseTable& table,
                                                      std::size_t r) {
  auto a = std::make_shared<SaltelliAnswer>();
  a->blocks = table.samples() / spec.saltelli_block();
  a->indices = sobol_of(spec, table, r, a->blocks);
  // From 4 base points: with 1 or 2 the bootstrap has nothing to resample.
  for (std::uint64_t m = 4; m < a->blocks; m *= 2) a->convergence.push_back({m, sobol_of(spec, table, r, m)});
  if (a->blocks > 0) a->convergence.push_back({a->blocks, a->indices});
  return a;
}

bool SaltelliAnswer::unreliable() const {
  return blocks > 0 && static_cast<double>(indices.base_samples) < kReliableBlockShare * static_cast<double>(blocks);
}

IndexVerdict index_verdict(const SobolIndices& s) {
  IndexVerdict v;
  v.widest = std::numeric_limits<double>::quiet_NaN();
  v.needed = v.widest;
  const std::vector<std::size_t>& order = s.ranking.order;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::size_t u = order[k];
    if (k > 0 && !(s.total[u] >= kIndexMatters)) break;
    // Within [0, 1], as shown: an index cannot leave it, so the part of an
    // interval beyond it says nothing.
    const double width = std::min(s.total_ci[2 * u + 1], 1.0) - std::max(s.total_ci[2 * u], 0.0);
    if (std::isnan(width)) return v;  // no intervals: no verdict
    if (k == 0 || width > v.widest) v.widest = width, v.unit = u;
  }
  if (std::isnan(v.widest)) return v;
  v.enough = v.widest <= kIndexIntervalWidth;
  const double ratio = v.widest / kIndexIntervalWidth;
  v.needed = std::ceil(static_cast<double>(s.base_samples) * ratio * ratio);
  return v;
}

}  // namespace treedyn::designs
