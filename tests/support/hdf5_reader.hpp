// Reading the files the binaries write back through the HDF5 C API, for
// tests. What is missing or unreadable is reported as a GoogleTest failure
// (ADD_FAILURE) naming it, and an empty value is returned, so a test goes on
// to report what else is wrong with the file.
#pragma once

#include <hdf5.h>

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace treedyn::testing {

// An HDF5 identifier closed with `close` on destruction (when valid).
class Hid {
 public:
  Hid(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~Hid() {
    if (id_ >= 0) close_(id_);
  }
  Hid(const Hid&) = delete;
  Hid& operator=(const Hid&) = delete;
  hid_t get() const { return id_; }
  bool ok() const { return id_ >= 0; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

// An HDF5 file opened read-only (closed on destruction); a file it cannot
// open is reported.
class H5File {
 public:
  explicit H5File(const std::filesystem::path& path);
  hid_t id() const { return file_.get(); }
  bool ok() const { return file_.ok(); }

 private:
  Hid file_;
};

// Whether the link `path` exists; false too when an intermediate group is
// missing (where H5Lexists itself fails).
bool exists(hid_t file, const std::string& path);

// ---------------------------------------------------------------------------
// Datasets

std::vector<hsize_t> shape(hid_t file, const std::string& path);

// A dataset read as doubles, with its shape.
struct DoubleArray {
  std::vector<hsize_t> dims;
  std::vector<double> data;  // row-major
  std::size_t rows() const { return dims.empty() ? 0 : dims[0]; }
  std::size_t cols() const { return dims.size() < 2 ? 1 : dims[1]; }
  double operator()(std::size_t r, std::size_t c) const { return data[r * cols() + c]; }
};

DoubleArray read_double_array(hid_t file, const std::string& path);
std::vector<double> read_doubles(hid_t file, const std::string& path);
std::vector<long long> read_integers(hid_t file, const std::string& path);

// A 1-D dataset of fixed-length strings.
std::vector<std::string> read_strings(hid_t file, const std::string& path);

// A dataset's raw content: shape, type (class, size, sign) and bytes, read in
// the native type of the file's type.
struct RawDataset {
  std::vector<hsize_t> dims;
  H5T_class_t type_class = H5T_NO_CLASS;
  std::size_t type_size = 0;
  int sign = -1;
  std::vector<unsigned char> bytes;
};

RawDataset read_raw(hid_t file, const std::string& path);

// Every dataset below `group` ("/stats"), as full paths, sorted.
std::vector<std::string> datasets_under(hid_t file, const std::string& group);

// ---------------------------------------------------------------------------
// Attributes of an object (a file, group or dataset)

bool has_attribute(hid_t object, const std::string& name);

// Fixed-length string attribute (scalar or 1-D) as a list of strings.
std::vector<std::string> read_string_attribute(hid_t object, const std::string& name);
// ... of the object at `path` in `file`.
std::vector<std::string> read_string_attribute(hid_t file, const std::string& path, const std::string& name);
// A string attribute that must hold exactly one string.
std::string read_single_string_attribute(hid_t object, const std::string& name);

long long read_integer_attribute(hid_t object, const std::string& name);
std::vector<double> read_double_attribute(hid_t object, const std::string& name);

// Byte-for-byte equality of every dataset under `groups`, and of the dataset
// lists themselves (GoogleTest failures name the first differing element).
void expect_identical_datasets(hid_t a, const std::string& a_name, hid_t b, const std::string& b_name,
                               const std::vector<std::string>& groups);

}  // namespace treedyn::testing
