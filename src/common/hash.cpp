#include "common/hash.hpp"

#include <xxhash.h>

#include <cstdio>
#include <new>

namespace treedyn {

struct StreamingHash::State {
  XXH3_state_t* xxh = XXH3_createState();
  ~State() { XXH3_freeState(xxh); }
};

std::uint64_t hash64(std::span<const char> bytes) { return XXH3_64bits(bytes.data(), bytes.size()); }

std::string hex64(std::uint64_t value) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
  return text;
}

StreamingHash::StreamingHash() : state_(std::make_unique<State>()) {
  if (state_->xxh == nullptr || XXH3_64bits_reset(state_->xxh) != XXH_OK) throw std::bad_alloc();
}

StreamingHash::~StreamingHash() = default;

void StreamingHash::update(std::span<const char> bytes) { XXH3_64bits_update(state_->xxh, bytes.data(), bytes.size()); }

std::uint64_t StreamingHash::digest() const { return XXH3_64bits_digest(state_->xxh); }

}  // namespace treedyn
