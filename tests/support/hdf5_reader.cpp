#include "support/hdf5_reader.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <sstream>

namespace treedyn::testing {

namespace {

std::vector<hsize_t> dims_of(hid_t space) {
  const int rank = H5Sget_simple_extent_ndims(space);
  std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 0)));
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  return dims;
}

// The dataset at `path`, or an invalid id after reporting it missing.
hid_t open_dataset(hid_t file, const std::string& path) {
  const hid_t id = exists(file, path) ? H5Dopen2(file, path.c_str(), H5P_DEFAULT) : H5I_INVALID_HID;
  if (id < 0) ADD_FAILURE() << "no dataset " << path;
  return id;
}

// Every element of the dataset at `path` converted to `memory_type`; its
// shape in `dims` when given.
template <class T>
std::vector<T> read_values(hid_t file, const std::string& path, hid_t memory_type, std::vector<hsize_t>* dims) {
  std::vector<T> v;
  Hid set(open_dataset(file, path), H5Dclose);
  if (!set.ok()) return v;
  Hid space(H5Dget_space(set.get()), H5Sclose);
  if (dims != nullptr) *dims = dims_of(space.get());
  v.resize(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.get())));
  if (!v.empty() && H5Dread(set.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0)
    ADD_FAILURE() << "cannot read dataset " << path;
  return v;
}

// `of` names the object in the messages (" of /samples/inputs"), or is empty.
std::vector<std::string> string_attribute(hid_t object, const std::string& name, const std::string& of) {
  std::vector<std::string> out;
  Hid attr(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose);
  if (!attr.ok()) {
    ADD_FAILURE() << "no attribute " << name << of;
    return out;
  }
  Hid type(H5Aget_type(attr.get()), H5Tclose);
  if (H5Tget_class(type.get()) != H5T_STRING) {
    ADD_FAILURE() << "attribute " << name << of << " is not a string";
    return out;
  }
  if (H5Tis_variable_str(type.get()) > 0) {
    Hid space(H5Aget_space(attr.get()), H5Sclose);
    const auto count = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.get()));
    std::vector<char*> pointers(count, nullptr);
    Hid memory_type(H5Tget_native_type(type.get(), H5T_DIR_ASCEND), H5Tclose);
    if (H5Aread(attr.get(), memory_type.get(), pointers.data()) < 0) {
      ADD_FAILURE() << "cannot read attribute " << name << of;
      return out;
    }
    for (char* p : pointers) out.emplace_back(p ? p : "");
    H5Dvlen_reclaim(memory_type.get(), space.get(), H5P_DEFAULT, pointers.data());
    return out;
  }
  const std::size_t width = H5Tget_size(type.get());
  Hid space(H5Aget_space(attr.get()), H5Sclose);
  const auto count = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.get()));
  std::vector<char> buffer(count * width + 1, '\0');
  Hid memory_type(H5Tget_native_type(type.get(), H5T_DIR_ASCEND), H5Tclose);
  if (H5Aread(attr.get(), memory_type.get(), buffer.data()) < 0) {
    ADD_FAILURE() << "cannot read attribute " << name << of;
    return out;
  }
  for (std::size_t k = 0; k < count; ++k) {
    const char* s = buffer.data() + k * width;
    out.emplace_back(s, strnlen(s, width));
  }
  return out;
}

}  // namespace

H5File::H5File(const std::filesystem::path& path)
    : file_(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose) {
  if (!file_.ok()) ADD_FAILURE() << "cannot open " << path << " with HDF5";
}

bool exists(hid_t file, const std::string& path) {
  // Check every prefix: H5Lexists fails on a missing intermediate group.
  std::size_t at = 0;
  while ((at = path.find('/', at + 1)) != std::string::npos)
    if (H5Lexists(file, path.substr(0, at).c_str(), H5P_DEFAULT) <= 0) return false;
  return H5Lexists(file, path.c_str(), H5P_DEFAULT) > 0;
}

std::vector<hsize_t> shape(hid_t file, const std::string& path) {
  Hid set(open_dataset(file, path), H5Dclose);
  if (!set.ok()) return {};
  Hid space(H5Dget_space(set.get()), H5Sclose);
  return dims_of(space.get());
}

DoubleArray read_double_array(hid_t file, const std::string& path) {
  DoubleArray a;
  a.data = read_values<double>(file, path, H5T_NATIVE_DOUBLE, &a.dims);
  return a;
}

std::vector<double> read_doubles(hid_t file, const std::string& path) {
  return read_values<double>(file, path, H5T_NATIVE_DOUBLE, nullptr);
}

std::vector<long long> read_integers(hid_t file, const std::string& path) {
  return read_values<long long>(file, path, H5T_NATIVE_LLONG, nullptr);
}

std::vector<std::string> read_strings(hid_t file, const std::string& path) {
  std::vector<std::string> out;
  {
    Hid set(open_dataset(file, path), H5Dclose);
    if (!set.ok()) return out;
    Hid type(H5Dget_type(set.get()), H5Tclose);
    if (H5Tget_class(type.get()) == H5T_STRING && H5Tis_variable_str(type.get()) > 0) {
      Hid space(H5Dget_space(set.get()), H5Sclose);
      const auto count = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.get()));
      std::vector<char*> pointers(count, nullptr);
      Hid memory_type(H5Tget_native_type(type.get(), H5T_DIR_ASCEND), H5Tclose);
      if (count > 0 && H5Dread(set.get(), memory_type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, pointers.data()) < 0) {
        ADD_FAILURE() << "cannot read dataset " << path;
        return out;
      }
      for (char* p : pointers) out.emplace_back(p ? p : "");
      if (count > 0) H5Dvlen_reclaim(memory_type.get(), space.get(), H5P_DEFAULT, pointers.data());
      return out;
    }
  }
  const RawDataset d = read_raw(file, path);
  if (d.type_class != H5T_STRING || d.type_size == 0) {
    ADD_FAILURE() << path << " is not a fixed-length string dataset";
    return out;
  }
  for (std::size_t k = 0; k < d.bytes.size() / d.type_size; ++k) {
    const char* s = reinterpret_cast<const char*>(d.bytes.data()) + k * d.type_size;
    out.emplace_back(s, strnlen(s, d.type_size));
  }
  return out;
}

RawDataset read_raw(hid_t file, const std::string& path) {
  RawDataset d;
  Hid set(open_dataset(file, path), H5Dclose);
  if (!set.ok()) return d;
  Hid space(H5Dget_space(set.get()), H5Sclose);
  d.dims = dims_of(space.get());
  Hid file_type(H5Dget_type(set.get()), H5Tclose);
  Hid native(H5Tget_native_type(file_type.get(), H5T_DIR_ASCEND), H5Tclose);
  if (H5Tget_class(file_type.get()) == H5T_STRING && H5Tis_variable_str(file_type.get()) > 0) {
    // Variable-length strings: their characters, each string NUL-ended (the
    // pointers HDF5 returns would differ between reads).
    d.type_class = H5T_STRING;
    d.type_size = 1;
    for (const std::string& s : read_strings(file, path)) {
      d.bytes.insert(d.bytes.end(), s.begin(), s.end());
      d.bytes.push_back(0);
    }
    return d;
  }
  d.type_class = H5Tget_class(native.get());
  d.type_size = H5Tget_size(native.get());
  if (d.type_class == H5T_INTEGER) d.sign = H5Tget_sign(native.get());
  const auto points = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.get()));
  d.bytes.assign(points * d.type_size, 0);
  if (points > 0 && H5Dread(set.get(), native.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, d.bytes.data()) < 0)
    ADD_FAILURE() << "cannot read dataset " << path;
  return d;
}

std::vector<std::string> datasets_under(hid_t file, const std::string& group) {
  std::vector<std::string> names;
  if (!exists(file, group)) {
    ADD_FAILURE() << "no group " << group;
    return names;
  }
  Hid g(H5Gopen2(file, group.c_str(), H5P_DEFAULT), H5Gclose);
  H5Lvisit(
      g.get(), H5_INDEX_NAME, H5_ITER_INC,
      [](hid_t, const char* name, const H5L_info_t*, void* data) -> herr_t {
        static_cast<std::vector<std::string>*>(data)->push_back(name);
        return 0;
      },
      &names);
  std::vector<std::string> out;
  for (const auto& n : names) {
    const std::string path = group + "/" + n;
    Hid object(H5Oopen(file, path.c_str(), H5P_DEFAULT), H5Oclose);
    if (object.ok() && H5Iget_type(object.get()) == H5I_DATASET) out.push_back(path);
  }
  std::sort(out.begin(), out.end());
  return out;
}

bool has_attribute(hid_t object, const std::string& name) { return H5Aexists(object, name.c_str()) > 0; }

std::vector<std::string> read_string_attribute(hid_t object, const std::string& name) {
  return string_attribute(object, name, "");
}

std::vector<std::string> read_string_attribute(hid_t file, const std::string& path, const std::string& name) {
  Hid object(H5Oopen(file, path.c_str(), H5P_DEFAULT), H5Oclose);
  if (!object.ok()) {
    ADD_FAILURE() << "no object " << path;
    return {};
  }
  return string_attribute(object.get(), name, " of " + path);
}

std::string read_single_string_attribute(hid_t object, const std::string& name) {
  const auto v = read_string_attribute(object, name);
  EXPECT_EQ(v.size(), 1u) << "attribute " << name << " should be a single string";
  return v.empty() ? std::string() : v[0];
}

long long read_integer_attribute(hid_t object, const std::string& name) {
  long long value = -1;
  Hid attr(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose);
  if (!attr.ok() || H5Aread(attr.get(), H5T_NATIVE_LLONG, &value) < 0)
    ADD_FAILURE() << "cannot read integer attribute " << name;
  return value;
}

std::vector<double> read_double_attribute(hid_t object, const std::string& name) {
  std::vector<double> v;
  Hid attr(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose);
  if (!attr.ok()) {
    ADD_FAILURE() << "no attribute " << name;
    return v;
  }
  Hid space(H5Aget_space(attr.get()), H5Sclose);
  v.resize(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.get())));
  if (H5Aread(attr.get(), H5T_NATIVE_DOUBLE, v.data()) < 0) ADD_FAILURE() << "cannot read " << name;
  return v;
}

void expect_identical_datasets(hid_t a, const std::string& a_name, hid_t b, const std::string& b_name,
                               const std::vector<std::string>& groups) {
  std::size_t compared = 0, bytes = 0;
  for (const std::string& group : groups) {
    const auto list_a = datasets_under(a, group), list_b = datasets_under(b, group);
    EXPECT_EQ(list_a, list_b) << "datasets under " << group << " differ between " << a_name << " and " << b_name;
    EXPECT_FALSE(list_a.empty()) << group << " holds no datasets";
    for (const std::string& path : list_a) {
      if (std::find(list_b.begin(), list_b.end(), path) == list_b.end()) continue;
      const RawDataset x = read_raw(a, path), y = read_raw(b, path);
      EXPECT_EQ(x.dims, y.dims) << path << ": shape differs, " << a_name << " vs " << b_name;
      EXPECT_EQ(x.type_class, y.type_class) << path;
      EXPECT_EQ(x.type_size, y.type_size) << path;
      EXPECT_EQ(x.sign, y.sign) << path;
      if (x.bytes.size() != y.bytes.size() || x.type_size == 0) {
        ADD_FAILURE() << path << ": " << x.bytes.size() << " vs " << y.bytes.size() << " bytes";
        continue;
      }
      ++compared;
      bytes += x.bytes.size();
      if (std::memcmp(x.bytes.data(), y.bytes.data(), x.bytes.size()) == 0) continue;
      std::size_t first = 0;
      while (x.bytes[first] == y.bytes[first]) ++first;
      const std::size_t element = first / x.type_size;
      std::ostringstream detail;
      if (x.type_class == H5T_FLOAT && x.type_size == sizeof(double)) {
        double u = 0.0, v = 0.0;
        std::memcpy(&u, x.bytes.data() + element * sizeof(double), sizeof(double));
        std::memcpy(&v, y.bytes.data() + element * sizeof(double), sizeof(double));
        detail.precision(17);
        detail << ": " << u << " vs " << v;
      }
      ADD_FAILURE() << path << " differs between " << a_name << " and " << b_name << " (first at flat element "
                    << element << detail.str() << ")";
    }
  }
  std::printf("  compared %zu datasets (%zu bytes) of %s with %s\n", compared, bytes, b_name.c_str(), a_name.c_str());
}

}  // namespace treedyn::testing
