// Reading back a treedyn HDF5 file (for `treedyn report`): whole datasets
// and attributes by path. Every failure throws IoError naming the path.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "ensemble/response_table.hpp"
#include "hdf5/hdf5.hpp"
#include "statistics/tolerance_check.hpp"

namespace treedyn::h5 {

class ReadFile {
 public:
  // Throws IoError when the file is not HDF5 or cannot be opened.
  explicit ReadFile(const std::filesystem::path& path);
  hid_t id() const { return file_.id(); }

  bool has(const std::string& path) const;  // a link, groups on the way included
  bool has_attribute(const std::string& object, const std::string& name) const;
  std::string string_attribute(const std::string& object, const std::string& name) const;
  double number_attribute(const std::string& object, const std::string& name) const;
  // Dataset values converted to the type; `dims` receives the shape.
  std::vector<double> doubles(const std::string& path, std::vector<hsize_t>* dims = nullptr) const;
  std::vector<long long> integers(const std::string& path) const;

 private:
  std::string path_;
  Handle file_;
};

// An ensemble file's /samples/status, inputs and responses as a table (the
// records rank 0 kept). Throws IoError when their shapes do not fit.
ensemble::ResponseTable response_table(const ReadFile& file, std::size_t inputs, std::size_t responses);

// Its /integration_check (the pilot's tolerance check), empty when it has none.
statistics::ToleranceCheck tolerance_check(const ReadFile& file);

}  // namespace treedyn::h5
