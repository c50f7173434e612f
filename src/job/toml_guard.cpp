#include "job/toml_guard.hpp"

#include <cstdio>

namespace treedyn {
namespace {

// Length of the UTF-8 sequence starting at text[at], or 0 if it is not one
// (overlong forms, surrogates and code points above U+10FFFF included).
std::size_t utf8_length(std::string_view text, std::size_t at) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[at + k]); };
  const unsigned char b0 = byte(0);
  std::size_t n = 0;
  unsigned code = 0;
  if (b0 < 0x80) return 1;
  if (b0 >= 0xC2 && b0 <= 0xDF)
    n = 2, code = b0 & 0x1Fu;
  else if (b0 >= 0xE0 && b0 <= 0xEF)
    n = 3, code = b0 & 0x0Fu;
  else if (b0 >= 0xF0 && b0 <= 0xF4)
    n = 4, code = b0 & 0x07u;
  else
    return 0;
  if (at + n > text.size()) return 0;
  for (std::size_t k = 1; k < n; ++k) {
    if ((byte(k) & 0xC0u) != 0x80u) return 0;
    code = (code << 6) | (byte(k) & 0x3Fu);
  }
  if ((n == 3 && code < 0x800) || (n == 4 && code < 0x10000) || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF))
    return 0;
  return n;
}

}  // namespace

bool guard_toml_text(std::string_view text, TomlGuardError& error) {
  enum class State { normal, comment, basic, literal, multi_basic, multi_literal };
  State state = State::normal;
  int line = 1, column = 1;
  auto fail = [&](const std::string& why) {
    error = {line, column, why};
    return false;
  };
  auto starts = [&](std::size_t at, std::string_view s) { return text.substr(at, s.size()) == s; };
  for (std::size_t at = 0; at < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[at]);
    if (c >= 0x80) {
      const std::size_t n = utf8_length(text, at);
      if (n == 0) {
        char hex[8];
        std::snprintf(hex, sizeof hex, "0x%02x", c);
        return fail(std::string("the byte ") + hex + " is not valid UTF-8 (save the file as UTF-8)");
      }
      if (state == State::normal)
        return fail(
            "a non-ASCII character outside a string or comment: TOML allows those only in quoted "
            "strings and comments (quote the key or the value)");
      at += n;
      ++column;
      continue;
    }
    std::size_t step = 1;
    switch (state) {
      case State::normal:
        if (c == '#')
          state = State::comment;
        else if (starts(at, "\"\"\""))
          state = State::multi_basic, step = 3;
        else if (starts(at, "'''"))
          state = State::multi_literal, step = 3;
        else if (c == '"')
          state = State::basic;
        else if (c == '\'')
          state = State::literal;
        break;
      case State::comment:
        if (c == '\n') state = State::normal;
        break;
      case State::basic:
        if (c == '\\' && at + 1 < text.size() && text[at + 1] != '\n')
          step = 2;
        else if (c == '"' || c == '\n')
          state = State::normal;  // an unterminated string: the parser says so
        break;
      case State::literal:
        if (c == '\'' || c == '\n') state = State::normal;
        break;
      case State::multi_basic:
        if (c == '\\' && at + 1 < text.size() && text[at + 1] != '\n')
          step = 2;
        else if (starts(at, "\"\"\""))
          state = State::normal, step = 3;
        break;
      case State::multi_literal:
        if (starts(at, "'''")) state = State::normal, step = 3;
        break;
    }
    for (std::size_t k = 0; k < step && at < text.size(); ++k, ++at) {
      if (text[at] == '\n') {
        ++line;
        column = 1;
      } else {
        ++column;
      }
    }
  }
  return true;
}

}  // namespace treedyn
