#include "common/buffer_pool.hpp"

#include <algorithm>

namespace treedyn {

ByteBuffer BufferPool::take(std::size_t bytes) {
  if (bytes == 0) return {};
  auto best = kept_.end();
  for (auto it = kept_.begin(); it != kept_.end(); ++it)
    if (it->size >= bytes && (best == kept_.end() || it->size < best->size)) best = it;
  if (best == kept_.end()) return {std::make_unique_for_overwrite<char[]>(bytes), bytes};
  ByteBuffer taken = std::move(*best);
  kept_bytes_ -= taken.size;
  kept_.erase(best);
  return taken;
}

void BufferPool::give_back(ByteBuffer buffer) {
  if (buffer.size == 0 || buffer.size > most_bytes_) return;
  std::size_t smaller = 0;  // what evicting every smaller buffer would free
  for (const ByteBuffer& k : kept_)
    if (k.size < buffer.size) smaller += k.size;
  if (kept_bytes_ - smaller + buffer.size > most_bytes_) return;  // would not fit even so: freed
  const auto by_size = [](const ByteBuffer& a, const ByteBuffer& b) { return a.size < b.size; };
  while (kept_bytes_ + buffer.size > most_bytes_) {
    const auto smallest = std::min_element(kept_.begin(), kept_.end(), by_size);
    kept_bytes_ -= smallest->size;
    kept_.erase(smallest);
  }
  kept_bytes_ += buffer.size;
  kept_.push_back(std::move(buffer));
}

}  // namespace treedyn
