// The recordable quantities of a trajectory: one table, each entry with its
// name, units, description, column labels and how to read it from a
// Recovered state.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "dynamics/recovered.hpp"
#include "job/job.hpp"
#include "model/model.hpp"

namespace treedyn {

struct QuantityInfo {
  std::string_view name;
  std::string_view units;
  std::string_view description;
  // Column labels for this model, e.g. "arm.x" (bodies in the user's order).
  std::vector<std::string> (*columns)(const Model& model, const OutputSpec& output);
  // Appends this instant's values, one per column, to `row`.
  void (*extract)(const Recovered& state, const OutputSpec& output, std::vector<double>& row);
};

// Every quantity a job may ask for, in the order they are written.
std::span<const QuantityInfo> quantity_catalogue();
const QuantityInfo* find_quantity(std::string_view name);

// By name (throws std::invalid_argument for an unknown one).
std::vector<std::string> quantity_columns(std::string_view name, const Model& model,
                                          const OutputSpec& output);
void extract_quantity(std::string_view name, const OutputSpec& output, const Recovered& state,
                      std::vector<double>& row);

}  // namespace treedyn
