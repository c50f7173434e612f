// Every dataset treedyn writes says what it is: units, a description and,
// where it has columns, their labels. The one helper both ensemble writers
// use (ensemble_file.cpp, answers_file.cpp).
#pragma once

#include <string>
#include <vector>

#include "hdf5/hdf5.hpp"

namespace treedyn::h5 {

inline void describe(hid_t set, const std::string& units, const std::string& description,
                     const std::vector<std::string>& columns) {
  write_attribute(set, "units", units);
  write_attribute(set, "description", description);
  if (!columns.empty()) write_attribute(set, "columns", columns);
}

template <class T>
void write_described_scalar(hid_t group, const char* name, T value, const std::string& units, const std::string& what) {
  Handle set = write_scalar(group, name, value);
  describe(set.id(), units, what, {});
}

}  // namespace treedyn::h5
