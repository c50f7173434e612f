#include "hdf5/read_file.hpp"

namespace treedyn::h5 {
namespace {

template <class T>
std::vector<T> read_all(hid_t file, const std::string& path, hid_t type, std::vector<hsize_t>* dims,
                        const std::string& file_name) {
  Handle set(H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose, "opening " + path + " in " + file_name);
  Handle space(H5Dget_space(set.id()), H5Sclose, "reading the shape of " + path);
  const int rank = H5Sget_simple_extent_ndims(space.id());
  std::vector<hsize_t> extent(static_cast<std::size_t>(std::max(rank, 0)));
  H5Sget_simple_extent_dims(space.id(), extent.data(), nullptr);
  const auto points = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.id()));
  std::vector<T> out(points);
  if (points > 0 && H5Dread(set.id(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    throw IoError("HDF5: reading " + path + " in " + file_name + " failed");
  if (dims) *dims = extent;
  return out;
}

}  // namespace

ReadFile::ReadFile(const std::filesystem::path& path) : path_(path.string()) {
  if (!std::filesystem::is_regular_file(path)) throw IoError(path_ + ": no such file");
  quiet_errors();
  if (H5Fis_hdf5(path.c_str()) <= 0) throw IoError(path_ + ": not an HDF5 file");
  file_ = Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "opening " + path_);
}

bool ReadFile::has(const std::string& path) const {
  std::size_t at = 0;
  while ((at = path.find('/', at + 1)) != std::string::npos)
    if (H5Lexists(file_.id(), path.substr(0, at).c_str(), H5P_DEFAULT) <= 0) return false;
  return H5Lexists(file_.id(), path.c_str(), H5P_DEFAULT) > 0;
}

bool ReadFile::has_attribute(const std::string& object, const std::string& name) const {
  return (object == "/" || has(object)) && H5Aexists_by_name(file_.id(), object.c_str(), name.c_str(), H5P_DEFAULT) > 0;
}

std::string ReadFile::string_attribute(const std::string& object, const std::string& name) const {
  Handle attr(H5Aopen_by_name(file_.id(), object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
              "opening attribute " + name + " of " + object + " in " + path_);
  Handle type(H5Aget_type(attr.id()), H5Tclose, "reading the type of attribute " + name);
  if (H5Tget_class(type.id()) != H5T_STRING) throw IoError(path_ + ": attribute " + name + " is not a string");
  if (H5Tis_variable_str(type.id()) > 0) {
    char* value = nullptr;
    Handle memory(H5Tget_native_type(type.id(), H5T_DIR_ASCEND), H5Tclose, "string type");
    if (H5Aread(attr.id(), memory.id(), &value) < 0) throw IoError(path_ + ": cannot read attribute " + name);
    std::string out = value ? value : "";
    H5free_memory(value);
    return out;
  }
  std::vector<char> buffer(H5Tget_size(type.id()) + 1, '\0');
  if (H5Aread(attr.id(), type.id(), buffer.data()) < 0) throw IoError(path_ + ": cannot read attribute " + name);
  return std::string(buffer.data());
}

double ReadFile::number_attribute(const std::string& object, const std::string& name) const {
  Handle attr(H5Aopen_by_name(file_.id(), object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
              "opening attribute " + name + " of " + object + " in " + path_);
  double value = 0.0;
  if (H5Aread(attr.id(), H5T_NATIVE_DOUBLE, &value) < 0) throw IoError(path_ + ": cannot read attribute " + name);
  return value;
}

std::vector<double> ReadFile::doubles(const std::string& path, std::vector<hsize_t>* dims) const {
  return read_all<double>(file_.id(), path, H5T_NATIVE_DOUBLE, dims, path_);
}

std::vector<long long> ReadFile::integers(const std::string& path) const {
  return read_all<long long>(file_.id(), path, H5T_NATIVE_LLONG, nullptr, path_);
}

ensemble::ResponseTable response_table(const ReadFile& file, std::size_t inputs, std::size_t responses) {
  std::vector<std::int32_t> status;
  for (long long s : file.integers("/samples/status")) status.push_back(static_cast<std::int32_t>(s));
  try {
    return ensemble::ResponseTable(
        std::move(status), inputs > 0 ? file.doubles("/samples/inputs") : std::vector<double>{},
        responses > 0 ? file.doubles("/samples/responses") : std::vector<double>{}, inputs, responses);
  } catch (const std::invalid_argument&) {
    throw IoError("/samples does not have the shape its job gives (an older layout?)");
  }
}

statistics::ToleranceCheck tolerance_check(const ReadFile& file) {
  statistics::ToleranceCheck check;
  if (!file.has("/integration_check")) return check;
  check.rtol = file.number_attribute("/integration_check", "rtol");
  check.atol = file.number_attribute("/integration_check", "atol");
  for (const long long k : file.integers("/integration_check/samples"))
    check.samples.push_back(static_cast<std::uint64_t>(k));
  check.change = file.doubles("/integration_check/change");
  check.spread = file.doubles("/integration_check/spread");
  return check;
}

}  // namespace treedyn::h5
