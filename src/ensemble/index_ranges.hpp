// A set of sample indices as sorted, disjoint [first, end) ranges, adjacent
// ones joined: the samples a resumed run already has, the samples the parts
// of a merge hold.
#pragma once

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <utility>
#include <vector>

namespace treedyn::ensemble {

class IndexRanges {
 public:
  using Range = std::pair<std::uint64_t, std::uint64_t>;

  // Adds [first, end), which must not start before the last range's end.
  void append(std::uint64_t first, std::uint64_t end) {
    if (first >= end) return;
    if (!ranges_.empty() && ranges_.back().second == first)
      ranges_.back().second = end;
    else
      ranges_.emplace_back(first, end);
  }
  bool contains(std::uint64_t k) const {
    const auto it = std::upper_bound(ranges_.begin(), ranges_.end(), k,
                                     [](std::uint64_t v, const Range& r) { return v < r.first; });
    return it != ranges_.begin() && k < std::prev(it)->second;
  }
  std::uint64_t count() const {
    std::uint64_t n = 0;
    for (const auto& [first, end] : ranges_) n += end - first;
    return n;
  }
  const std::vector<Range>& ranges() const { return ranges_; }
  bool empty() const { return ranges_.empty(); }

 private:
  std::vector<Range> ranges_;
};

}  // namespace treedyn::ensemble
