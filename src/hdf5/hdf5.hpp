// A small RAII layer over the HDF5 C API: every handle closes itself, every
// failing call throws IoError naming what it was doing.
#pragma once

#include <hdf5.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "process/atomic_file.hpp"
#include "process/drop_behind.hpp"

namespace treedyn::h5 {

// An HDF5 call failed (its own words are in the message): a file error, exit 4.
class IoError : public process::FileError {
 public:
  using process::FileError::FileError;
};

// One owned hid_t, closed with the matching H5*close.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer close, const std::string& what);  // throws if id < 0
  ~Handle() { reset(); }
  Handle(Handle&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = H5I_INVALID_HID; }
  Handle& operator=(Handle&& o) noexcept;
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  hid_t id() const { return id_; }
  void reset();
  // Closes now and returns the close call's status (reset() ignores it).
  herr_t close_now();

 private:
  hid_t id_ = H5I_INVALID_HID;
  Closer close_ = nullptr;
};

// Writes a new file through process::AtomicFile: HDF5 creates it under the
// temporary name; commit() closes it, flushes it to the disk and renames it
// into place. Destroyed without commit(), it removes the temporary file, and
// a signal that ends the process removes it too: a failed or killed run
// leaves nothing behind. Every dataset and group handle must be closed
// before commit().
class File {
 public:
  explicit File(std::filesystem::path final_path);
  ~File();
  File(const File&) = delete;
  File& operator=(const File&) = delete;
  hid_t id() const { return handle_.id(); }
  // After a batch of rows: lets the kernel drop what is already on the disk
  // of a file written front to back (process/drop_behind.hpp). Throws
  // IoError when starting the writeback fails.
  void drop_written_pages();
  void commit();

 private:
  process::AtomicFile target_;
  Handle handle_;
  std::optional<process::DropBehind> drop_behind_;  // none where HDF5 gives no descriptor
};

// HDF5 prints no error stack of its own (treedyn reports errors itself);
// done by every Handle, needed before a call that does not make one.
void quiet_errors();

// Throws IoError("HDF5: <what> failed") when `status` is negative.
void check(herr_t status, const std::string& what);

Handle create_group(hid_t parent, const std::string& name);

// A 2-D dataset rows x columns of doubles, chunked and deflate-compressed.
Handle write_matrix(hid_t parent, const std::string& name, std::span<const double> data, std::size_t rows,
                    std::size_t columns);
// 1-D datasets.
Handle write_vector(hid_t parent, const std::string& name, std::span<const double> data);

// Keeps the first `rows` rows of a chunked dataset (its first dimension cut
// to `rows`; nothing happens when it has no more).
void keep_rows(hid_t dataset, std::size_t rows);

// An N-dimensional dataset of `type` (e.g. H5T_NATIVE_DOUBLE), chunked and
// compressed, written whole.
Handle write_array(hid_t parent, const std::string& name, hid_t type, const void* data, std::span<const hsize_t> dims);
// A scalar dataset (no chunks, no compression): one number a reader gets
// with f[path][()].
Handle write_scalar(hid_t parent, const std::string& name, double value);
Handle write_scalar(hid_t parent, const std::string& name, std::uint64_t value);
// A dataset (rows, row_shape...) of `type` created empty, filled later (by
// RowDataset, row_dataset.hpp, or write_strings_at) as records arrive out
// of order: chunks of `chunk_rows` whole rows (0: about 64 KiB), deflated
// at kRowsDeflateLevel (RowDataset skips it for a raw chunk). `fill` (one value of `type`) is what a row never
// written reads as; HDF5's default is zero.
Handle create_rows(hid_t parent, const std::string& name, hid_t type, std::size_t rows,
                   std::span<const hsize_t> row_shape, std::size_t chunk_rows = 0, const void* fill = nullptr);
// Rows are written while the samples run, by rank 0, which integrates too:
// level 1 writes them markedly faster than level 4 for a file barely larger
// (BENCHMARKS.md, "Longer runs" and "Where the code's design numbers come
// from").
constexpr unsigned kRowsDeflateLevel = 1;
// Strings, one per row, filled later. Every string this layer writes
// (datasets and attributes) is variable-length UTF-8: h5py gives `str`.
// A row never written is a null string: h5py reads it as empty (b''),
// h5dump shows NULL, the C API gives a null pointer.
Handle create_string_rows(hid_t parent, const std::string& name, std::size_t rows, std::size_t chunk_rows = 0);
// texts[k] into row rows[k] (increasing), the other rows untouched.
void write_strings_at(hid_t dataset, std::span<const hsize_t> rows, std::span<const char* const> texts);

void write_attribute(hid_t object, const std::string& name, const std::string& value);
void write_attribute(hid_t object, const std::string& name, double value);
void write_attribute(hid_t object, const std::string& name, long long value);
void write_attribute(hid_t object, const std::string& name, const std::vector<std::string>& values);
void write_attribute(hid_t object, const std::string& name, std::span<const double> values);
void write_attribute(hid_t object, const std::string& name, std::span<const long long> values);

}  // namespace treedyn::h5
