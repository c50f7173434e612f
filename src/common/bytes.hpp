// The one byte codec of treedyn: what goes into checkpoints, part files and
// MPI messages. Trivially copyable values in the machine's own byte order
// (a checkpoint is only ever read by the build that wrote it), vectors and
// strings with a 64-bit length before them. A reader never trusts a length:
// every read is checked against what is left, and a short or damaged buffer
// throws DecodeError naming what was being read.
#pragma once

#include <cstdint>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace treedyn {

class DecodeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Appends to a byte vector it does not own.
class ByteWriter {
 public:
  explicit ByteWriter(std::vector<char>& out) : out_(out) {}

  template <class T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const char*>(&value);
    out_.insert(out_.end(), p, p + sizeof(T));
  }
  template <class T>
  void put_vector(std::span<const T> values) {
    static_assert(std::is_trivially_copyable_v<T>);
    put(static_cast<std::uint64_t>(values.size()));
    put_bytes({reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T)});
  }
  template <class T>
  void put_vector(const std::vector<T>& values) {
    put_vector(std::span<const T>(values));
  }
  void put_text(std::string_view text) {
    put(static_cast<std::uint64_t>(text.size()));
    put_bytes({text.data(), text.size()});
  }
  // Raw bytes, no length.
  void put_bytes(std::span<const char> bytes) { out_.insert(out_.end(), bytes.begin(), bytes.end()); }

 private:
  std::vector<char>& out_;
};

// Reads a buffer it does not own; `what` names it in errors ("checkpoint
// /x/part-0-rank1.state").
class ByteReader {
 public:
  ByteReader(std::span<const char> bytes, std::string what) : bytes_(bytes), what_(std::move(what)) {}

  template <class T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    T value;
    std::memcpy(&value, take(sizeof(T)).data(), sizeof(T));
    return value;
  }
  template <class T>
  std::vector<T> get_vector() {
    std::vector<T> values;
    get_vector_into(values);
    return values;
  }
  // Into `values`, reusing its capacity (a decoder of many records keeps
  // its vectors).
  template <class T>
  void get_vector_into(std::vector<T>& values) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto count = get<std::uint64_t>();
    if (count > left() / sizeof(T)) fail("truncated");
    values.resize(static_cast<std::size_t>(count));
    if (count > 0) std::memcpy(values.data(), take(count * sizeof(T)).data(), count * sizeof(T));
  }
  std::string get_text() {
    std::string text;
    get_text_into(text);
    return text;
  }
  void get_text_into(std::string& text) {
    const auto count = get<std::uint64_t>();
    const std::span<const char> s = take(count);
    text.assign(s.data(), s.size());
  }
  // `count` raw bytes.
  std::span<const char> get_bytes(std::uint64_t count) { return take(count); }

  std::size_t left() const { return bytes_.size() - at_; }
  bool done() const { return at_ == bytes_.size(); }
  std::size_t position() const { return at_; }
  const std::string& what() const { return what_; }
  [[noreturn]] void fail(const std::string& why) const { throw DecodeError(what_ + " is damaged (" + why + ")"); }

 private:
  std::span<const char> take(std::uint64_t count) {
    if (count > left()) fail("truncated");
    const std::span<const char> s = bytes_.subspan(at_, static_cast<std::size_t>(count));
    at_ += static_cast<std::size_t>(count);
    return s;
  }

  std::span<const char> bytes_;
  std::size_t at_ = 0;
  std::string what_;
};

}  // namespace treedyn
