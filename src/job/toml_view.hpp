// Typed, strict access to one TOML table of a job file. Every getter names the
// field's full path and its place in the file when it refuses a value, and
// check_keys() rejects unknown keys with a "did you mean" suggestion.
#pragma once

#include <toml++/toml.h>

#include <initializer_list>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "common/format.hpp"
#include "common/linalg.hpp"
#include "job/job_error.hpp"

namespace treedyn {

class TomlView {
 public:
  TomlView(const toml::table& table, std::string path, const std::string& file)
      : table_(table), path_(std::move(path)), file_(file) {}

  const toml::table& table() const { return table_; }
  const std::string& path() const { return path_; }
  const std::string& file() const { return file_; }
  std::string field(std::string_view key) const;  // "body.mass"

  // Unknown keys are errors; the nearest allowed key is suggested.
  void check_keys(std::span<const std::string_view> allowed) const;
  void check_keys(std::initializer_list<std::string_view> allowed) const {
    check_keys(std::span<const std::string_view>(allowed.begin(), allowed.size()));
  }
  bool has(std::string_view key) const { return table_.contains(key); }

  [[noreturn]] void fail(std::string_view key, const std::string& what) const;
  [[noreturn]] void fail_at(const toml::node* node, std::string_view key, const std::string& what) const;

  std::optional<double> number(std::string_view key) const;
  double number(std::string_view key, double fallback) const;
  double required_number(std::string_view key) const;
  std::optional<long> integer(std::string_view key) const;
  std::optional<std::string> string(std::string_view key) const;
  std::string required_string(std::string_view key) const;
  std::optional<bool> boolean(std::string_view key) const;
  std::optional<Vec3> vec3(std::string_view key) const;
  std::optional<std::vector<double>> numbers(std::string_view key) const;
  // A 3x3 matrix given as three rows, or a single number s meaning s * E.
  std::optional<Mat3> mat3_or_scalar(std::string_view key) const;
  std::optional<TomlView> subtable(std::string_view key) const;
  std::vector<TomlView> table_array(std::string_view key) const;  // [[key]]

 private:
  const toml::node* node(std::string_view key) const { return table_.get(key); }

  const toml::table& table_;
  std::string path_;
  const std::string& file_;
};

// "; did you mean 'X'?" for the allowed word nearest to `word` (edit
// distance), or "" when none is near.
std::string did_you_mean(std::string_view word, std::span<const std::string_view> allowed);

// Source position of a node, for errors raised after reading.
int line_of(const toml::node& node);
int column_of(const toml::node& node);

}  // namespace treedyn
