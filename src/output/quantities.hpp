// The recordable quantities of a trajectory: name, units, description, column
// labels, and how to read each from a Recovered state.
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
};

// Every quantity a job may ask for, in the order they are written.
std::span<const QuantityInfo> quantity_catalogue();
const QuantityInfo* find_quantity(std::string_view name);

// Column labels of a quantity for this model (e.g. "arm.x"), user order.
std::vector<std::string> quantity_columns(std::string_view name, const Model& model,
                                          const OutputSpec& output);

// Appends the quantity's columns at this instant to `row`.
void extract_quantity(std::string_view name, const Model& model, const OutputSpec& output,
                      const Recovered& state, std::vector<double>& row);

}  // namespace treedyn
