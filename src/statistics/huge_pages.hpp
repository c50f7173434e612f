// Memory for the statistics' histogram counters: tens of megabytes, every
// part of which a fold touches. From the C++ allocator each 4 KiB page costs
// a fault on its first touch, every run, on every rank. Here the array gets
// a mapping of its own, aligned to 2 MiB and marked for transparent huge
// pages (honoured where the kernel's THP setting is `madvise` or `always`),
// so a few faults do it (BENCHMARKS.md, "A run's fixed costs"). Without THP
// the pages stay 4 KiB.
#pragma once

#include <cstddef>
#include <memory>
#include <new>

namespace treedyn::statistics {

// `bytes` of zeroed memory, 2 MiB aligned. Throws std::bad_alloc when the
// mapping (or, where the kernel tells, its pages) cannot be had.
void* map_huge_pages(std::size_t bytes);
void unmap_huge_pages(void* p, std::size_t bytes) noexcept;

// A std::vector allocator over map_huge_pages, for arrays of megabytes
// (below 2 MiB it would waste most of a huge page: the default allocator).
template <class T>
struct HugePageAllocator {
  using value_type = T;
  static constexpr std::size_t kHugePage = std::size_t{2} << 20;

  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

  T* allocate(std::size_t n) {
    if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_alloc();
    if (!mapped(n)) return std::allocator<T>().allocate(n);
    return static_cast<T*>(map_huge_pages(n * sizeof(T)));
  }
  void deallocate(T* p, std::size_t n) noexcept {
    if (!mapped(n))
      std::allocator<T>().deallocate(p, n);
    else
      unmap_huge_pages(p, n * sizeof(T));
  }
  // Whether n values get a mapping of their own: not under AddressSanitizer,
  // whose allocator puts a red zone after the array (an index one past its
  // end would land in the mapping's unused tail, unseen).
  static bool mapped(std::size_t n) {
#if defined(__SANITIZE_ADDRESS__)
    (void)n;
    return false;
#else
    return n * sizeof(T) >= kHugePage;
#endif
  }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const noexcept {
    return true;
  }
};

}  // namespace treedyn::statistics
