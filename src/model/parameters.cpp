#include "model/parameters.hpp"

#include <algorithm>
#include <array>
#include <sstream>
#include <stdexcept>

namespace treedyn {

int Parameter::size() const {
  switch (shape) {
    case ParameterShape::scalar:
      return 1;
    case ParameterShape::vector3:
      return 3;
    case ParameterShape::matrix3:
      return 9;
    case ParameterShape::list:
      return length;
  }
  return 1;
}

std::string_view component_name(ParameterShape shape, int component) {
  static constexpr std::array<std::string_view, 3> kAxes{"x", "y", "z"};
  static constexpr std::array<std::string_view, 9> kEntries{"xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz"};
  switch (shape) {
    case ParameterShape::scalar:
      return "";
    case ParameterShape::vector3:
      return kAxes.at(static_cast<std::size_t>(component));
    case ParameterShape::matrix3:
      return kEntries.at(static_cast<std::size_t>(component));
    case ParameterShape::list:
      return "";
  }
  return "";
}

std::string ValidRange::describe(const std::string& unit) const {
  if (!bounded()) return "any value";
  std::ostringstream s;
  s << (low_open ? "> " : ">= ") << low << (unit == "1" ? "" : " " + unit);
  return s.str();
}

int ParameterTable::add(std::string name, std::string unit, ParameterShape shape, std::string enters,
                        std::span<const double> nominal, ValidRange valid) {
  Parameter p{std::move(name), std::move(unit), std::move(enters), shape, static_cast<int>(nominal_.size()), valid};
  if (shape == ParameterShape::list) p.length = static_cast<int>(nominal.size());
  if (static_cast<int>(nominal.size()) != p.size())
    throw std::logic_error("parameter " + p.name + ": wrong number of nominal entries");
  if (!by_name_.emplace(p.name, parameters_.size()).second)
    throw std::logic_error("parameter " + p.name + " defined twice");
  nominal_.insert(nominal_.end(), nominal.begin(), nominal.end());
  parameters_.push_back(std::move(p));
  return parameters_.back().offset;
}

const Parameter* ParameterTable::find(std::string_view name) const {
  const auto it = by_name_.find(std::string(name));
  return it == by_name_.end() ? nullptr : &parameters_[it->second];
}

const Parameter& ParameterTable::owner(int index) const {
  // Parameters are stored in offset order: the last one starting at or before index.
  const auto it = std::upper_bound(parameters_.begin(), parameters_.end(), index,
                                   [](int i, const Parameter& p) { return i < p.offset; });
  if (it == parameters_.begin() || index < 0 || index >= static_cast<int>(nominal_.size()))
    throw std::out_of_range("parameter entry out of range");
  return *(it - 1);
}

std::string ParameterTable::entry_name(int index) const {
  const Parameter& p = owner(index);
  if (p.shape == ParameterShape::scalar) return p.name;
  if (p.shape == ParameterShape::list) return p.name + "[" + std::to_string(index - p.offset + 1) + "]";
  return p.name + "." + std::string(component_name(p.shape, index - p.offset));
}

void ParameterTable::set_nominal(std::span<const double> values) {
  if (values.size() != nominal_.size())
    throw std::invalid_argument("ParameterTable::set_nominal: the vector has the wrong size");
  nominal_.assign(values.begin(), values.end());
}

}  // namespace treedyn
