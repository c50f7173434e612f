// A first pass over a job file's bytes before toml++ sees them. Debian 12's
// toml++ 3.3.0 reaches __builtin_unreachable (undefined behaviour) on some
// non-ASCII input outside strings, e.g. the bytes c6 bb 27 (upstream
// marzer/tomlplusplus#295, fixed by #305 after that release). TOML 1.0 allows
// non-ASCII characters only inside strings and comments, so refusing them
// anywhere else, and any invalid UTF-8, loses no valid job and keeps the
// parser away from that path.
#pragma once

#include <string>
#include <string_view>

namespace treedyn {

struct TomlGuardError {
  int line = 0, column = 0;  // 1-based, columns in bytes
  std::string message;
};

// True when the text may go to the parser; else `error` says where and why.
bool guard_toml_text(std::string_view text, TomlGuardError& error);

}  // namespace treedyn
