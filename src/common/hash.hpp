// The one hash of treedyn: XXH3, 64 bits (xxHash, Debian's libxxhash). It
// names a job text (a checkpoint belongs to one job), a build (the
// executable's bytes) and checks every checkpoint and part file. It finds
// accidents (a truncated file, a flipped bit), not attacks.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>

namespace treedyn {

std::uint64_t hash64(std::span<const char> bytes);
inline std::uint64_t hash64(const std::string& text) { return hash64(std::span<const char>(text)); }

// 16 lower-case hex digits.
std::string hex64(std::uint64_t value);

// The same hash over bytes that arrive in pieces (a file written as it goes).
class StreamingHash {
 public:
  StreamingHash();
  ~StreamingHash();
  StreamingHash(const StreamingHash&) = delete;
  StreamingHash& operator=(const StreamingHash&) = delete;
  void update(std::span<const char> bytes);
  std::uint64_t digest() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace treedyn
