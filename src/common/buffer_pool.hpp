// Byte buffers kept for reuse, up to a bound on their bytes together: a
// receiver that takes a message of n bytes gets a buffer of at least n
// without allocating, zeroing or faulting in fresh pages each time, which
// for messages of megabytes costs more than receiving them.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

namespace treedyn {

// A buffer of `size` bytes, uninitialised when new.
struct ByteBuffer {
  std::unique_ptr<char[]> data;
  std::size_t size = 0;
};

class BufferPool {
 public:
  explicit BufferPool(std::size_t most_bytes) : most_bytes_(most_bytes) {}
  // The smallest kept buffer of at least `bytes`, else a new one (none for
  // 0 bytes).
  ByteBuffer take(std::size_t bytes);
  // `buffer` kept for a later take(); beyond the bound, smaller buffers go
  // first (the largest are the ones worth keeping), and a buffer that would
  // not fit even then is freed, nothing evicted for it.
  void give_back(ByteBuffer buffer);
  std::size_t kept_bytes() const { return kept_bytes_; }
  std::size_t kept_buffers() const { return kept_.size(); }

 private:
  std::size_t most_bytes_;
  std::size_t kept_bytes_ = 0;
  std::vector<ByteBuffer> kept_;
};

}  // namespace treedyn
