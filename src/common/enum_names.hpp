// One table per enumeration gives its names: printing, parsing and the list of
// allowed values in error messages all read the same table, so they cannot
// drift apart.
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <utility>

namespace treedyn {

template <class E, std::size_t N>
using NameTable = std::array<std::pair<E, std::string_view>, N>;

template <class E, std::size_t N>
constexpr std::string_view name_in(const NameTable<E, N>& table, E value) {
  for (const auto& [v, n] : table)
    if (v == value) return n;
  return "?";
}

template <class E, std::size_t N>
bool parse_in(const NameTable<E, N>& table, std::string_view text, E& out) {
  for (const auto& [v, n] : table)
    if (n == text) {
      out = v;
      return true;
    }
  return false;
}

// "\"a\", \"b\" or \"c\"", for messages saying what is allowed.
template <class E, std::size_t N>
std::string choices(const NameTable<E, N>& table) {
  std::string out;
  for (std::size_t k = 0; k < N; ++k) {
    if (k > 0) out += k + 1 == N ? " or " : ", ";
    out += "\"" + std::string(table[k].second) + "\"";
  }
  return out;
}

}  // namespace treedyn
