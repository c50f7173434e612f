#include "hdf5/hdf5.hpp"

#include <unistd.h>

#include <algorithm>
#include <system_error>

namespace treedyn::h5 {
namespace {

// HDF5 prints its own error stack by default; treedyn reports errors itself.
// Nor may HDF5 close files from its exit handler: after a failed write it
// would crash there, turning a clean exit code into a segfault.
void silence_hdf5() {
  static const bool done = [] {
    // H5dont_atexit works only before the library initialises itself, which
    // any other call (H5Eset_auto2 included) does: it must come first.
    H5dont_atexit();
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)done;
}

// Variable-length UTF-8: what h5py reads as `str` and MATLAB as a string.
Handle text_type() {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose, "copying the string type");
  check(H5Tset_size(type.id(), H5T_VARIABLE), "making a variable-length string type");
  check(H5Tset_cset(type.id(), H5T_CSET_UTF8), "setting the UTF-8 character set");
  return type;
}

std::vector<const char*> pointers_to(const std::vector<std::string>& values) {
  std::vector<const char*> out;
  for (const std::string& v : values) out.push_back(v.c_str());
  return out;
}

// About 64 KiB a chunk, whole rows. Each chunk costs a fixed amount (the
// filter's set-up; HDF5 indexes and writes each): chunks of a few rows cost
// rank 0 more in that than in compressing, and compress worse
// (BENCHMARKS.md, "Longer runs"). A chunk whose
// rows arrive in several writes waits in memory until it is whole: the
// numbers' in RowDataset (row_dataset.hpp), the strings' in the chunk cache
// (rows_cache).
hsize_t rows_per_chunk(hsize_t row_bytes, hsize_t rows) {
  return std::clamp<hsize_t>(65536 / std::max<hsize_t>(row_bytes, 1), 1, std::max<hsize_t>(rows, 1));
}

// A row dataset's chunk cache: 4 chunks, the ones whose rows are still
// arriving (the records of other ranks' samples in flight), not HDF5's
// default 1 MiB, which rank 0 would fill for each per-sample dataset it
// serves: /samples/reason, and the others when HDF5 cuts them (keep_rows).
// w0 = 1: a chunk written whole leaves the cache first.
Handle rows_cache() {
  Handle access(H5Pcreate(H5P_DATASET_ACCESS), H5Pclose, "creating dataset access properties");
  check(H5Pset_chunk_cache(access.id(), 101, 4 * 65536, 1.0), "setting the chunk cache");
  return access;
}

// Bytes one value of `type` takes in a chunk: a variable-length string is
// a 16-byte reference into the file's heap there, though H5Tget_size gives
// the size of the pointer in memory.
hsize_t stored_bytes(hid_t type) {
  const htri_t variable = H5Tis_variable_str(type);
  check(variable, "inspecting a datatype");
  if (variable > 0) return 16;
  const std::size_t size = H5Tget_size(type);
  if (size == 0) throw IoError("HDF5: getting a datatype's size failed");
  return size;
}

Handle simple_space(std::span<const hsize_t> dims) {
  return Handle(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose,
                "creating a dataspace");
}

Handle chunked_deflate(std::span<const hsize_t> dims) {
  Handle plist(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "creating dataset properties");
  std::vector<hsize_t> chunk(dims.begin(), dims.end());
  chunk[0] = rows_per_chunk((dims.size() > 1 ? dims[1] : 1) * sizeof(double), dims[0]);
  check(H5Pset_chunk(plist.id(), static_cast<int>(chunk.size()), chunk.data()), "setting chunks");
  check(H5Pset_shuffle(plist.id()), "setting the shuffle filter");
  check(H5Pset_deflate(plist.id(), 4), "setting deflate compression");
  return plist;
}

Handle write_dataset(hid_t parent, const std::string& name, hid_t type, const void* data, std::span<const hsize_t> dims,
                     bool compress) {
  Handle space = simple_space(dims);
  bool empty = false;
  for (hsize_t d : dims) empty = empty || d == 0;
  Handle plist =
      compress && !empty ? chunked_deflate(dims) : Handle(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "properties");
  Handle set(H5Dcreate2(parent, name.c_str(), type, space.id(), H5P_DEFAULT, plist.id(), H5P_DEFAULT), H5Dclose,
             "creating dataset " + name);
  if (!empty) check(H5Dwrite(set.id(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "writing dataset " + name);
  return set;
}

void attribute(hid_t object, const std::string& name, hid_t type, hid_t space, const void* data) {
  Handle attr(H5Acreate2(object, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
              "creating attribute " + name);
  check(H5Awrite(attr.id(), type, data), "writing attribute " + name);
}

}  // namespace

void quiet_errors() { silence_hdf5(); }

void check(herr_t status, const std::string& what) {
  if (status < 0) throw IoError("HDF5: " + what + " failed");
}

Handle::Handle(hid_t id, Closer close, const std::string& what) : id_(id), close_(close) {
  silence_hdf5();
  if (id < 0) throw IoError("HDF5: " + what + " failed");
}

Handle& Handle::operator=(Handle&& o) noexcept {
  if (this != &o) {
    reset();
    id_ = o.id_;
    close_ = o.close_;
    o.id_ = H5I_INVALID_HID;
  }
  return *this;
}

void Handle::reset() {
  if (id_ >= 0 && close_) close_(id_);
  id_ = H5I_INVALID_HID;
}

herr_t Handle::close_now() {
  const herr_t status = id_ >= 0 && close_ ? close_(id_) : 0;
  id_ = H5I_INVALID_HID;
  return status;
}

File::File(std::filesystem::path final_path) : target_(std::move(final_path), process::AtomicFile::Create::by_caller) {
  silence_hdf5();
  // The 1.8 file format (object header v2) moves an attribute that does not
  // fit the 64 KiB object header into dense storage, so the per-column
  // attributes of a model with thousands of bodies fit; every HDF5 >= 1.8
  // (2008), h5py and MATLAB read it.
  Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "creating file access properties");
  if (H5Pset_libver_bounds(access.id(), H5F_LIBVER_V18, H5F_LIBVER_LATEST) < 0)
    throw IoError("output " + target_.path().string() + ": HDF5 refused the 1.8 file format");
  const hid_t id = H5Fcreate(target_.temporary().c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.id());
  if (id < 0)
    throw IoError("output " + target_.path().string() + ": cannot create the file (HDF5 refused " +
                  target_.temporary().string() + ")");
  handle_ = Handle(id, H5Fclose, "creating " + target_.temporary().string());
  // Only the default driver's handle is a descriptor (HDF5_DRIVER may
  // choose another).
  Handle used(H5Fget_access_plist(id), H5Pclose, "getting the file's access properties");
  void* descriptor = nullptr;
  if (H5Pget_driver(used.id()) == H5FD_SEC2 && H5Fget_vfd_handle(id, H5P_DEFAULT, &descriptor) >= 0 && descriptor)
    drop_behind_.emplace(*static_cast<int*>(descriptor), "output " + target_.path().string());
}

void File::drop_written_pages() {
  if (!drop_behind_) return;
  try {
    drop_behind_->after_writes();
  } catch (const process::FileError& e) {
    throw IoError(e.what());
  }
}

File::~File() { handle_.reset(); }  // before target_ removes the temporary

void File::commit() {
  const std::string path = target_.path().string();
  if (H5Fflush(handle_.id(), H5F_SCOPE_GLOBAL) < 0)
    throw IoError("output " + path + ": writing the file to disk failed (is the disk full?)");
  drop_behind_.reset();  // its descriptor is closed below
  // Every object must be closed by now, or closing the file would be deferred
  // past the rename.
  if (H5Fget_obj_count(handle_.id(), H5F_OBJ_ALL) > 1)
    throw IoError("output " + path + ": internal error, objects still open at commit");
  // A failed close (the last metadata not written: a full disk) must not be
  // renamed as complete.
  if (handle_.close_now() < 0) throw IoError("output " + path + ": closing the file failed (is the disk full?)");
  try {
    target_.commit();
  } catch (const process::FileError& e) {
    throw IoError("output " + std::string(e.what()));
  }
}

Handle create_group(hid_t parent, const std::string& name) {
  return Handle(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                "creating group " + name);
}

Handle write_matrix(hid_t parent, const std::string& name, std::span<const double> data, std::size_t rows,
                    std::size_t columns) {
  const hsize_t dims[2] = {rows, columns};
  return write_dataset(parent, name, H5T_NATIVE_DOUBLE, data.data(), dims, true);
}

Handle write_array(hid_t parent, const std::string& name, hid_t type, const void* data, std::span<const hsize_t> dims) {
  return write_dataset(parent, name, type, data, dims, true);
}

namespace {
Handle scalar_dataset(hid_t parent, const std::string& name, hid_t type, const void* value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose, "creating a scalar dataspace");
  Handle set(H5Dcreate2(parent, name.c_str(), type, space.id(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose,
             "creating dataset " + name);
  check(H5Dwrite(set.id(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, value), "writing dataset " + name);
  return set;
}
}  // namespace

Handle write_scalar(hid_t parent, const std::string& name, double value) {
  return scalar_dataset(parent, name, H5T_NATIVE_DOUBLE, &value);
}

Handle write_scalar(hid_t parent, const std::string& name, std::uint64_t value) {
  return scalar_dataset(parent, name, H5T_NATIVE_UINT64, &value);
}

Handle create_rows(hid_t parent, const std::string& name, hid_t type, std::size_t rows,
                   std::span<const hsize_t> row_shape, std::size_t chunk_rows, const void* fill) {
  std::vector<hsize_t> dims{rows}, chunk{1};
  hsize_t row_bytes = stored_bytes(type);
  for (hsize_t extent : row_shape) {
    dims.push_back(extent);
    chunk.push_back(std::max<hsize_t>(extent, 1));
    row_bytes *= std::max<hsize_t>(extent, 1);
  }
  chunk[0] =
      chunk_rows > 0 ? std::clamp<hsize_t>(chunk_rows, 1, std::max<hsize_t>(rows, 1)) : rows_per_chunk(row_bytes, rows);
  Handle space = simple_space(dims);
  Handle plist(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "creating dataset properties");
  if (fill) check(H5Pset_fill_value(plist.id(), type, fill), "setting a fill value");
  if (rows > 0) {
    check(H5Pset_chunk(plist.id(), static_cast<int>(dims.size()), chunk.data()), "setting chunks");
    check(H5Pset_deflate(plist.id(), kRowsDeflateLevel), "setting deflate compression");
  }
  Handle access = rows_cache();
  return Handle(H5Dcreate2(parent, name.c_str(), type, space.id(), H5P_DEFAULT, plist.id(), access.id()), H5Dclose,
                "creating dataset " + name);
}

void keep_rows(hid_t dataset, std::size_t rows) {
  Handle space(H5Dget_space(dataset), H5Sclose, "getting a dataspace");
  const int rank = H5Sget_simple_extent_ndims(space.id());
  std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 1)));
  H5Sget_simple_extent_dims(space.id(), dims.data(), nullptr);
  if (dims[0] <= rows) return;
  dims[0] = rows;
  check(H5Dset_extent(dataset, dims.data()), "cutting a dataset to the samples used");
}

Handle create_string_rows(hid_t parent, const std::string& name, std::size_t rows, std::size_t chunk_rows) {
  Handle type = text_type();
  return create_rows(parent, name, type.id(), rows, {}, chunk_rows);
}

void write_strings_at(hid_t dataset, std::span<const hsize_t> rows, std::span<const char* const> texts) {
  if (rows.size() != texts.size()) throw std::logic_error("write_strings_at: a text for every row");
  if (rows.empty()) return;
  Handle type = text_type();
  // Variable-length strings go through HDF5's type conversion, whose buffer
  // (1 MiB by default) is allocated and zeroed on every write, a large cost
  // for a few rows (BENCHMARKS.md, "Samples per second"). A buffer for these
  // rows is enough.
  Handle transfer(H5Pcreate(H5P_DATASET_XFER), H5Pclose, "creating transfer properties");
  check(H5Pset_buffer(transfer.id(), std::max<std::size_t>(4096, 64 * rows.size()), nullptr, nullptr),
        "sizing the conversion buffer");
  Handle file_space(H5Dget_space(dataset), H5Sclose, "getting a dataspace");
  check(H5Sselect_elements(file_space.id(), H5S_SELECT_SET, rows.size(), rows.data()), "selecting rows");
  const hsize_t count[1] = {rows.size()};
  Handle memory_space = simple_space(count);
  check(H5Dwrite(dataset, type.id(), memory_space.id(), file_space.id(), transfer.id(), texts.data()), "writing rows");
}

Handle write_vector(hid_t parent, const std::string& name, std::span<const double> data) {
  const hsize_t dims[1] = {data.size()};
  return write_dataset(parent, name, H5T_NATIVE_DOUBLE, data.data(), dims, true);
}

void write_attribute(hid_t object, const std::string& name, const std::string& value) {
  Handle type = text_type();
  Handle space(H5Screate(H5S_SCALAR), H5Sclose, "creating a scalar dataspace");
  const char* text = value.c_str();
  attribute(object, name, type.id(), space.id(), &text);
}

void write_attribute(hid_t object, const std::string& name, double value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose, "creating a scalar dataspace");
  attribute(object, name, H5T_NATIVE_DOUBLE, space.id(), &value);
}

void write_attribute(hid_t object, const std::string& name, long long value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose, "creating a scalar dataspace");
  attribute(object, name, H5T_NATIVE_LLONG, space.id(), &value);
}

void write_attribute(hid_t object, const std::string& name, const std::vector<std::string>& values) {
  const std::vector<const char*> pointers = pointers_to(values);
  Handle type = text_type();
  const hsize_t dims[1] = {values.size()};
  Handle space = simple_space(dims);
  attribute(object, name, type.id(), space.id(), pointers.data());
}

void write_attribute(hid_t object, const std::string& name, std::span<const long long> values) {
  const hsize_t dims[1] = {values.size()};
  Handle space = simple_space(dims);
  attribute(object, name, H5T_NATIVE_LLONG, space.id(), values.data());
}

void write_attribute(hid_t object, const std::string& name, std::span<const double> values) {
  const hsize_t dims[1] = {values.size()};
  Handle space = simple_space(dims);
  attribute(object, name, H5T_NATIVE_DOUBLE, space.id(), values.data());
}

}  // namespace treedyn::h5
