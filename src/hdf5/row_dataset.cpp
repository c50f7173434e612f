#include "hdf5/row_dataset.hpp"

#include <algorithm>
#include <cstring>

#include "hdf5/deflate.hpp"

namespace treedyn::h5 {

RowDataset::RowDataset(hid_t parent, const std::string& name, hid_t type, std::size_t rows,
                       std::span<const hsize_t> row_shape, std::size_t chunk_rows, const void* fill)
    : name_(name), rows_(rows), rank_(1 + row_shape.size()) {
  // The chunks go to the file as they are in memory: the type must be this
  // machine's own (H5T_NATIVE_*), whose bytes HDF5 stores unconverted.
  Handle native(H5Tget_native_type(type, H5T_DIR_DEFAULT), H5Tclose, "getting a native type");
  const htri_t same = H5Tequal(native.id(), type);
  check(same, "comparing a type with its native one");
  const std::size_t value_bytes = H5Tget_size(type);
  if (same == 0 || value_bytes == 0)
    throw IoError("HDF5: " + name + ": rows of a native number type only (this one is stored converted)");
  row_bytes_ = value_bytes;
  for (hsize_t extent : row_shape) row_bytes_ *= extent;
  // A row of no values has no chunk to write: HDF5 refuses chunks there.
  if (row_bytes_ == 0) throw IoError("HDF5: " + name + ": rows of no values (a row shape with a 0)");
  set_ = create_rows(parent, name, type, rows, row_shape, chunk_rows, fill);
  if (rows == 0) return;  // no chunks
  Handle plist(H5Dget_create_plist(set_.id()), H5Pclose, "getting dataset properties");
  std::vector<hsize_t> chunk(rank_);
  check(H5Pget_chunk(plist.id(), static_cast<int>(rank_), chunk.data()), "getting the chunk shape");
  chunk_rows_ = chunk[0];
  fill_row_.assign(row_bytes_, 0);
  if (fill)
    for (std::size_t at = 0; at < row_bytes_; at += value_bytes) std::memcpy(fill_row_.data() + at, fill, value_bytes);
  stored_.assign((rows + chunk_rows_ - 1) / chunk_rows_, false);
}

std::size_t RowDataset::rows_in(std::size_t c) const { return std::min(chunk_rows_, rows_ - c * chunk_rows_); }

void RowDataset::write(std::size_t first_row, std::size_t rows, const void* data) {
  if (rows == 0) return;
  if (first_row + rows > rows_ || first_row + rows < first_row)
    throw IoError("HDF5: " + name_ + ": writing rows " + std::to_string(first_row) + " .. " +
                  std::to_string(first_row + rows - 1) + " of " + std::to_string(rows_));
  ++writes_;
  const auto* from = static_cast<const unsigned char*>(data);
  for (std::size_t row = first_row, end = first_row + rows; row < end;) {
    const std::size_t c = row / chunk_rows_, within = row - c * chunk_rows_;
    const std::size_t n = std::min(end - row, chunk_rows_ - within);
    Chunk& chunk = held(c);
    std::memcpy(chunk.bytes.data() + within * row_bytes_, from + (row - first_row) * row_bytes_, n * row_bytes_);
    for (std::size_t k = within; k < within + n; ++k)
      if (!chunk.written[k]) {
        chunk.written[k] = true;
        ++chunk.count;
      }
    chunk.last_write = writes_;
    if (chunk.count == rows_in(c)) {
      store(c, chunk);
      held_.erase(c);
    }
    row += n;
  }
  while (held_.size() > kHeldChunks) store_least_recent();
}

// The chunk written longest ago leaves memory first: its missing rows are a
// slow rank's block, while the others' rows arrive now.
void RowDataset::store_least_recent() {
  auto oldest = std::min_element(held_.begin(), held_.end(), [](const auto& a, const auto& b) {
    return a.second.last_write < b.second.last_write;
  });
  store(oldest->first, oldest->second);
  stored_partly_[oldest->first] = std::move(oldest->second.written);
  held_.erase(oldest);
}

// Chunk c in memory: held already, or read back from the file (stored
// before its last rows came, or rewritten), or new (the fill). Added to
// `held_` only once whole, so a failed read leaves nothing half-made.
RowDataset::Chunk& RowDataset::held(std::size_t c) {
  auto at = held_.find(c);
  if (at != held_.end()) return at->second;
  Chunk chunk;
  if (stored_[c]) {
    chunk = load(c);
  } else {
    chunk.bytes.resize(chunk_rows_ * row_bytes_);
    for (std::size_t k = 0; k < chunk_rows_; ++k)
      std::memcpy(chunk.bytes.data() + k * row_bytes_, fill_row_.data(), row_bytes_);
    chunk.written.assign(chunk_rows_, false);
  }
  return held_.emplace(c, std::move(chunk)).first->second;
}

RowDataset::Chunk RowDataset::load(std::size_t c) {
  const std::string what = "HDF5: " + name_ + ": reading back chunk " + std::to_string(c);
  std::vector<hsize_t> offset(rank_, 0);
  offset[0] = c * chunk_rows_;
  hsize_t size = 0;
  check(H5Dget_chunk_storage_size(set_.id(), offset.data(), &size), name_ + ": getting a stored chunk's size");
  stream_.resize(size);
  std::uint32_t filters = 0;
  check(H5Dread_chunk(set_.id(), H5P_DEFAULT, offset.data(), &filters, stream_.data()),
        name_ + ": reading a stored chunk");
  Chunk chunk;
  chunk.bytes.resize(chunk_rows_ * row_bytes_);
  if (filters == 0)
    inflate(stream_, chunk.bytes, what.c_str());
  else if (size == chunk.bytes.size())
    std::memcpy(chunk.bytes.data(), stream_.data(), size);  // HDF5 stored it unfiltered
  else
    throw IoError(what + ": " + std::to_string(size) + " bytes stored unfiltered, not " +
                  std::to_string(chunk.bytes.size()));
  auto partly = stored_partly_.find(c);
  if (partly != stored_partly_.end()) {
    chunk.written = std::move(partly->second);
    stored_partly_.erase(partly);
  } else {
    chunk.written.assign(chunk_rows_, false);
    std::fill_n(chunk.written.begin(), rows_in(c), true);
  }
  // Rows past a cut (keep_rows) do not count.
  chunk.count = static_cast<std::size_t>(
      std::count(chunk.written.begin(), chunk.written.begin() + static_cast<long>(rows_in(c)), true));
  return chunk;
}

void RowDataset::store(std::size_t c, const Chunk& chunk) {
  deflate(chunk.bytes, kRowsDeflateLevel, stream_);
  std::vector<hsize_t> offset(rank_, 0);
  offset[0] = c * chunk_rows_;
  check(H5Dwrite_chunk(set_.id(), H5P_DEFAULT, 0, offset.data(), stream_.size(), stream_.data()),
        name_ + ": writing rows");
  stored_[c] = true;
  ++stores_;
}

// Each chunk leaves `held_` as soon as it is stored: a failed store (a full
// disk) leaves the rest held, as they were.
void RowDataset::flush() {
  for (auto at = held_.begin(); at != held_.end();) {
    store(at->first, at->second);
    if (at->second.count < rows_in(at->first)) stored_partly_[at->first] = std::move(at->second.written);
    at = held_.erase(at);
  }
}

void RowDataset::keep_rows(std::size_t rows) {
  if (rows >= rows_) return;
  const std::size_t chunks = (rows + chunk_rows_ - 1) / chunk_rows_;
  held_.erase(held_.lower_bound(chunks), held_.end());  // wholly past the cut: never stored
  flush();
  h5::keep_rows(set_.id(), rows);
  rows_ = rows;
  stored_.resize(chunks);
  stored_partly_.erase(stored_partly_.lower_bound(chunks), stored_partly_.end());
}

}  // namespace treedyn::h5
