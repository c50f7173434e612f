#include "job/toml_view.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace treedyn {
namespace {

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

}  // namespace

std::string did_you_mean(std::string_view word, std::span<const std::string_view> allowed) {
  std::string_view best;
  std::size_t best_distance = 1000;
  for (std::string_view a : allowed) {
    const std::size_t d = edit_distance(word, a);
    if (d < best_distance) best_distance = d, best = a;
  }
  if (best_distance <= std::max<std::size_t>(2, word.size() / 3)) return "; did you mean '" + std::string(best) + "'?";
  return "";
}

namespace {

std::string type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a number";
    case toml::node_type::boolean:
      return "a boolean";
    default:
      return "a date or time";
  }
}

}  // namespace

int line_of(const toml::node& node) { return static_cast<int>(node.source().begin.line); }
int column_of(const toml::node& node) { return static_cast<int>(node.source().begin.column); }

std::string TomlView::field(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

void TomlView::fail(std::string_view key, const std::string& what) const { fail_at(node(key), key, what); }

void TomlView::fail_at(const toml::node* at, std::string_view key, const std::string& what) const {
  const toml::node& where = at ? *at : static_cast<const toml::node&>(table_);
  throw JobError(file_, line_of(where), column_of(where), field(key), what);
}

void TomlView::check_keys(std::span<const std::string_view> allowed) const {
  for (const auto& [key, value] : table_) {
    const std::string_view k = key.str();
    if (std::find(allowed.begin(), allowed.end(), k) != allowed.end()) continue;
    std::ostringstream what;
    what << "unknown key '" << k << "'" << did_you_mean(k, allowed);
    what << " Allowed here:";
    for (std::string_view a : allowed) what << " " << a;
    throw JobError(file_, line_of(value), column_of(value), field(k), what.str());
  }
}

std::optional<double> TomlView::number(std::string_view key) const {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  if (!n->is_number()) fail(key, "expected a number, got " + type_name(*n));
  const double v = n->value<double>().value();
  if (!std::isfinite(v)) fail(key, "must be finite (no inf or nan)");
  return v;
}

double TomlView::number(std::string_view key, double fallback) const { return number(key).value_or(fallback); }

double TomlView::required_number(std::string_view key) const {
  const auto v = number(key);
  if (!v) fail(key, "missing required field (a number)");
  return *v;
}

std::optional<long> TomlView::integer(std::string_view key) const {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  if (!n->is_integer()) fail(key, "expected an integer, got " + type_name(*n));
  return static_cast<long>(n->value<int64_t>().value());
}

std::optional<std::string> TomlView::string(std::string_view key) const {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  if (!n->is_string()) fail(key, "expected a string, got " + type_name(*n));
  return n->value<std::string>().value();
}

std::string TomlView::required_string(std::string_view key) const {
  const auto v = string(key);
  if (!v) fail(key, "missing required field (a string)");
  return *v;
}

std::optional<bool> TomlView::boolean(std::string_view key) const {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  if (!n->is_boolean()) fail(key, "expected true or false, got " + type_name(*n));
  return n->value<bool>().value();
}

std::optional<std::vector<double>> TomlView::numbers(std::string_view key) const {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  const toml::array* a = n->as_array();
  if (!a) fail(key, "expected an array of numbers, got " + type_name(*n));
  std::vector<double> out;
  for (const toml::node& e : *a) {
    if (!e.is_number()) fail_at(&e, key, "expected an array of numbers, found " + type_name(e));
    const double v = e.value<double>().value();
    if (!std::isfinite(v)) fail_at(&e, key, "must be finite (no inf or nan)");
    out.push_back(v);
  }
  return out;
}

std::optional<Vec3> TomlView::vec3(std::string_view key) const {
  const auto v = numbers(key);
  if (!v) return std::nullopt;
  if (v->size() != 3) fail(key, "expected 3 numbers [x, y, z], got " + std::to_string(v->size()));
  return Vec3((*v)[0], (*v)[1], (*v)[2]);
}

std::optional<Mat3> TomlView::mat3_or_scalar(std::string_view key) const {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  if (n->is_number()) return required_number(key) * Mat3::Identity();
  const toml::array* rows = n->as_array();
  const char* expected = "expected a number or 3 rows of 3 numbers [[a,b,c],[d,e,f],[g,h,i]]";
  if (!rows || rows->size() != 3) fail(key, expected);
  Mat3 m;
  for (int r = 0; r < 3; ++r) {
    const toml::array* row = (*rows)[static_cast<std::size_t>(r)].as_array();
    if (!row || row->size() != 3) fail(key, expected);
    for (int c = 0; c < 3; ++c) {
      const toml::node& e = (*row)[static_cast<std::size_t>(c)];
      if (!e.is_number()) fail_at(&e, key, expected);
      m(r, c) = e.value<double>().value();
    }
  }
  if (!m.allFinite()) fail(key, "must be finite (no inf or nan)");
  return m;
}

std::optional<TomlView> TomlView::subtable(std::string_view key) const {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  const toml::table* t = n->as_table();
  if (!t) fail(key, "expected a table, got " + type_name(*n));
  return TomlView(*t, field(key), file_);
}

std::vector<TomlView> TomlView::table_array(std::string_view key) const {
  std::vector<TomlView> out;
  const toml::node* n = node(key);
  if (!n) return out;
  const toml::array* a = n->as_array();
  if (!a) fail(key, "expected an array of tables ([[" + std::string(key) + "]]), got " + type_name(*n));
  std::size_t index = 0;
  for (const toml::node& e : *a) {
    const toml::table* t = e.as_table();
    if (!t) fail_at(&e, key, "expected tables ([[" + std::string(key) + "]]), found " + type_name(e));
    out.emplace_back(*t, field(key) + "[" + std::to_string(++index) + "]", file_);
  }
  return out;
}

}  // namespace treedyn
