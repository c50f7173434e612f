// The statistics' counters' memory (src/statistics/huge_pages.hpp): zeroed,
// 2 MiB aligned from 2 MiB on (where the kernel can place huge pages), the
// default allocator's below, and std::bad_alloc for what cannot be mapped.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <new>
#include <vector>

#include "statistics/huge_pages.hpp"

namespace treedyn::ensemble {
namespace {

using Counters = std::vector<std::uint32_t, HugePageAllocator<std::uint32_t>>;
constexpr std::size_t kHuge = HugePageAllocator<char>::kHugePage;

TEST(HugePages, ArraysOfEverySizeAreZeroedAndHoldWhatIsWritten) {
  for (std::size_t bytes : {std::size_t{4}, kHuge - 4, kHuge, kHuge + 4, 5 * kHuge + 12}) {
    SCOPED_TRACE(bytes);
    Counters counts(bytes / sizeof(std::uint32_t));
    EXPECT_TRUE(std::all_of(counts.begin(), counts.end(), [](std::uint32_t c) { return c == 0; }));
    const auto address = reinterpret_cast<std::uintptr_t>(counts.data());
    if (bytes >= kHuge) {
      EXPECT_EQ(address % kHuge, 0u) << "a mapping of its own, on a huge page's boundary";
    }
    for (std::size_t k = 0; k < counts.size(); ++k) counts[k] = static_cast<std::uint32_t>(k * 2654435761u);
    const Counters copy = counts;  // the copy gets its own mapping
    EXPECT_NE(copy.data(), counts.data());
    for (std::size_t k = 0; k < counts.size(); ++k)
      ASSERT_EQ(copy[k], static_cast<std::uint32_t>(k * 2654435761u)) << k;
  }
}

TEST(HugePages, WhatCannotBeMappedIsBadAlloc) {
  HugePageAllocator<std::uint32_t> allocator;
  EXPECT_THROW(allocator.allocate(std::numeric_limits<std::size_t>::max() / 2), std::bad_alloc);  // overflows
  EXPECT_THROW(allocator.allocate(std::size_t{1} << 60), std::bad_alloc);  // 4 EiB: no address space holds it
}

}  // namespace
}  // namespace treedyn::ensemble
