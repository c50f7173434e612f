// The statistics' counters' memory (src/statistics/huge_pages.hpp): zeroed,
// from 2 MiB on a mapping of its own on a huge page's boundary (the default
// allocator's below, and under AddressSanitizer), given back whole, and
// std::bad_alloc for what cannot be mapped.
#include "statistics/huge_pages.hpp"

#include <gtest/gtest.h>
#include <sys/mman.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <limits>
#include <new>
#include <vector>

namespace treedyn::statistics {
namespace {

using Counters = std::vector<std::uint32_t, HugePageAllocator<std::uint32_t>>;
constexpr std::size_t kHuge = HugePageAllocator<char>::kHugePage;

// Whether any page of [p, p + bytes) is mapped (mincore says ENOMEM where
// none is).
bool any_page_mapped(const void* p, std::size_t bytes) {
  std::vector<unsigned char> pages(bytes / 4096 + 1);
  const auto start = reinterpret_cast<std::uintptr_t>(p) / 4096 * 4096;
  for (std::uintptr_t page = start; page < reinterpret_cast<std::uintptr_t>(p) + bytes; page += 4096)
    if (mincore(reinterpret_cast<void*>(page), 4096, pages.data()) == 0 || errno != ENOMEM) return true;
  return false;
}

TEST(HugePages, ArraysOfEverySizeAreZeroedHoldWhatIsWrittenAndAreGivenBackWhole) {
  for (std::size_t bytes : {std::size_t{4}, kHuge - 4, kHuge, kHuge + 4, 5 * kHuge + 12}) {
    SCOPED_TRACE(bytes);
    const std::size_t n = bytes / sizeof(std::uint32_t);
    const bool mapped = HugePageAllocator<std::uint32_t>::mapped(n);
    const void* where = nullptr;
    {
      Counters counts(n);
      where = counts.data();
      EXPECT_TRUE(std::all_of(counts.begin(), counts.end(), [](std::uint32_t c) { return c == 0; }));
      if (mapped) {
        EXPECT_EQ(reinterpret_cast<std::uintptr_t>(counts.data()) % kHuge, 0u) << "on a huge page's boundary";
      }
      for (std::size_t k = 0; k < n; ++k) counts[k] = static_cast<std::uint32_t>(k * 2654435761u);
      const Counters copy = counts;
      for (std::size_t k = 0; k < n; ++k) ASSERT_EQ(copy[k], static_cast<std::uint32_t>(k * 2654435761u)) << k;
    }
    if (mapped) {
      // The mapping, rounded up to whole huge pages, is gone with the vector.
      EXPECT_FALSE(any_page_mapped(where, (bytes + kHuge - 1) / kHuge * kHuge));
    }
  }
}

TEST(HugePages, WhatCannotBeMappedIsBadAlloc) {
  constexpr std::size_t most = std::numeric_limits<std::size_t>::max();
  EXPECT_THROW(HugePageAllocator<std::uint32_t>().allocate(most / 2),
               std::bad_alloc);                                        // its bytes overflow
  EXPECT_THROW(map_huge_pages(most - 3), std::bad_alloc);              // rounded up to huge pages, it would wrap
  EXPECT_THROW(map_huge_pages(std::size_t{1} << 62), std::bad_alloc);  // 4 EiB: no address space holds it
#if !defined(__SANITIZE_ADDRESS__)  // there std::allocator's, which AddressSanitizer aborts for sizes like these
  EXPECT_THROW(HugePageAllocator<std::uint32_t>().allocate(most / 4), std::bad_alloc);
  EXPECT_THROW(HugePageAllocator<std::uint32_t>().allocate(std::size_t{1} << 60), std::bad_alloc);
#endif
}

}  // namespace
}  // namespace treedyn::statistics
