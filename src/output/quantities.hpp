// The recordable quantities of a trajectory: one table, each entry with its
// name, units, description, column labels and how to read it from a
// Recovered state.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "dynamics/recovered.hpp"
#include "model/model.hpp"
#include "output/output_spec.hpp"

namespace treedyn {

struct QuantityInfo {
  std::string_view name;
  std::string_view units;
  std::string_view description;
  // Column labels for this model, e.g. "arm.x" (bodies in the user's order).
  std::vector<std::string> (*columns)(const Model& model, const OutputSpec& output);
  // Writes this instant's values, one per column, at `out` (as many as
  // `columns` names) and returns the place after the last: the recorder's
  // row has its place already, so a quantity neither checks nor grows
  // storage; the recorder checks the row's length.
  double* (*extract)(const Recovered& state, const OutputSpec& output, double* out);
  // The parts of Recovered beyond the always-recovered ones it reads
  // (RecoveredPart flags, dynamics/recovered.hpp).
  unsigned needs = 0;
};

// Every quantity a job may ask for, in the order they are written.
std::span<const QuantityInfo> quantity_catalogue();
const QuantityInfo* find_quantity(std::string_view name);

// The flat columns of the recorded quantities (output.quantities, in order):
// one row per output time holds every column of every quantity.
struct ColumnLayout {
  std::vector<std::string> quantity;            // names, in order
  std::vector<const QuantityInfo*> info;        // their catalogue entries
  std::vector<std::size_t> offset;              // first column of each quantity
  std::vector<std::vector<std::string>> names;  // column labels of each quantity
  std::size_t columns = 0;
  unsigned needs = 0;  // the quantities' RecoveredPart flags, together
};
// Units of column `column` of quantity `quantity` (an index into the
// layout): a quantity with mixed units ("m, m/s, m/s^2") lists one per equal
// group of columns.
std::string column_unit(const ColumnLayout& layout, std::size_t quantity, std::size_t column);
// Throws std::invalid_argument for a quantity not in the catalogue.
ColumnLayout column_layout(const Model& model, const OutputSpec& output);

}  // namespace treedyn
