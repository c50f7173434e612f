#include "statistics/huge_pages.hpp"

#include <sys/mman.h>

#include <cstdint>

namespace treedyn::statistics {
namespace {

constexpr std::size_t kAlign = HugePageAllocator<char>::kHugePage;

std::size_t rounded_up(std::size_t bytes) { return (bytes + kAlign - 1) / kAlign * kAlign; }

}  // namespace

void* map_huge_pages(std::size_t bytes) {
  if (bytes > SIZE_MAX - 2 * kAlign) throw std::bad_alloc();  // the sizes below would wrap
  const std::size_t size = rounded_up(bytes);
  // One huge page more than needed, then the unaligned head and the tail
  // given back: the kernel places huge pages only at 2 MiB boundaries.
  void* raw = mmap(nullptr, size + kAlign, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (raw == MAP_FAILED) throw std::bad_alloc();
  const auto start = reinterpret_cast<std::uintptr_t>(raw);
  const std::uintptr_t aligned = (start + kAlign - 1) / kAlign * kAlign;
  if (aligned > start) munmap(raw, aligned - start);
  if (const std::size_t tail = start + size + kAlign - (aligned + size); tail > 0)
    munmap(reinterpret_cast<void*>(aligned + size), tail);
  void* p = reinterpret_cast<void*>(aligned);
  madvise(p, size, MADV_HUGEPAGE);  // a hint: without THP the pages stay 4 KiB
  return p;
}

void unmap_huge_pages(void* p, std::size_t bytes) noexcept { munmap(p, rounded_up(bytes)); }

}  // namespace treedyn::statistics
