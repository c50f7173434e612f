// Wall-clock helpers the benchmarks share: elapsed seconds and medians.
#pragma once

#include <algorithm>
#include <chrono>
#include <vector>

namespace treedyn::bench {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// The median of `v` (the upper one of an even count); 0 for none.
inline double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace treedyn::bench
