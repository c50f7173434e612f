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

void RowDataset::write_chunk_whole(std::size_t c, std::span<const unsigned char> bytes, bool deflated) {
  const std::string what = "HDF5: " + name_ + ": a sent chunk " + std::to_string(c);
  if (c >= stored_.size() || rows_in(c) != chunk_rows_) throw IoError(what + ": not a whole chunk of the dataset");
  if (held_.contains(c) || stored_[c]) {
    std::vector<unsigned char> rows(chunk_rows_ * row_bytes_);
    if (deflated)
      inflate(bytes, rows, what.c_str());
    else if (bytes.size() == rows.size())
      std::memcpy(rows.data(), bytes.data(), rows.size());
    else
      throw IoError(what + ": " + std::to_string(bytes.size()) + " bytes raw, not " + std::to_string(rows.size()));
    write(c * chunk_rows_, chunk_rows_, rows.data());
    return;
  }
  if (!deflated && bytes.size() != chunk_rows_ * row_bytes_)
    throw IoError(what + ": " + std::to_string(bytes.size()) + " bytes raw, not " +
                  std::to_string(chunk_rows_ * row_bytes_));
  write_chunk(c, bytes, deflated);
  stored_[c] = true;
  ++stores_;
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

std::vector<hsize_t> RowDataset::chunk_offset(std::size_t c) const {
  std::vector<hsize_t> offset(rank_, 0);
  offset[0] = c * chunk_rows_;
  return offset;
}

// From the chunk index: H5Dread_chunk reports the mask of HDF5's record of
// the chunk looked up last, stale after a direct write (open_again).
RowDataset::StoredChunk RowDataset::stored_chunk(std::size_t c) const {
  StoredChunk stored;
  stored.offset = chunk_offset(c);
  unsigned mask = 0;
  haddr_t address = 0;
  check(H5Dget_chunk_info_by_coord(set_.id(), stored.offset.data(), &mask, &address, &stored.bytes),
        name_ + ": finding stored chunk " + std::to_string(c));
  stored.deflated = (mask & 1u) == 0;
  return stored;
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
  const StoredChunk stored = stored_chunk(c);
  stream_.resize(stored.bytes);
  std::uint32_t ignored = 0;  // from HDF5's record of the last lookup: stored.deflated is right
  check(H5Dread_chunk(set_.id(), H5P_DEFAULT, stored.offset.data(), &ignored, stream_.data()),
        name_ + ": reading a stored chunk");
  Chunk chunk;
  chunk.bytes.resize(chunk_rows_ * row_bytes_);
  if (stored.deflated)
    inflate(stream_, chunk.bytes, what.c_str());
  else if (stored.bytes == chunk.bytes.size())
    std::memcpy(chunk.bytes.data(), stream_.data(), stored.bytes);
  else
    throw IoError(what + ": " + std::to_string(stored.bytes) + " bytes stored unfiltered, not " +
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

// Deflated unless the dataset's trial found deflate not worth it. Always
// deflated: a chunk with rows missing, or the dataset's last, shorter one,
// since the fill in their place shrinks to nothing (BENCHMARKS.md, "A run's
// fixed costs"); and the
// chunk a cut goes through: HDF5 rewrites that chunk (the rows past the
// cut become the fill) through its deflate filter and, as for a direct
// write, records the new mask only where the size changed.
void RowDataset::store(std::size_t c, const Chunk& chunk) {
  const bool deflated = deflating_ || chunk.count < chunk_rows_ || c == cut_chunk_;
  std::span<const unsigned char> bytes = chunk.bytes;
  if (deflated) {
    if (all_fill(chunk.bytes)) {  // the same bytes as deflating it again
      if (fill_stream_.empty()) deflate(chunk.bytes, kRowsDeflateLevel, fill_stream_);
      bytes = fill_stream_;
    } else {
      deflate(chunk.bytes, kRowsDeflateLevel, stream_);
      bytes = stream_;
    }
    if (chunk.count == chunk_rows_ && !stored_[c])  // no fill flatters it; each chunk judged once
      judge_deflate(chunk.bytes.size(), bytes.size());
  }
  write_chunk(c, bytes, deflated);
  stored_[c] = true;
  ++stores_;
}

// Every row the fill: the first row is, and each row equals the one
// before it (the chunk compared with itself one row further on).
bool RowDataset::all_fill(const std::vector<unsigned char>& bytes) const {
  return std::memcmp(bytes.data(), fill_row_.data(), row_bytes_) == 0 &&
         std::memcmp(bytes.data() + row_bytes_, bytes.data(), bytes.size() - row_bytes_) == 0;
}

// HDF5 (H5D__chunk_direct_write, 1.10 to 1.14) records a rewritten
// chunk's filter mask only where its stored size changes: a chunk that
// changes form at the same size is first written one byte shorter.
void RowDataset::write_chunk(std::size_t c, std::span<const unsigned char> bytes, bool deflated) {
  const std::vector<hsize_t> offset = chunk_offset(c);
  const std::uint32_t mask = deflated ? 0 : 1;                              // bit 0: deflate (filter 0) skipped
  const StoredChunk before = stored_[c] ? stored_chunk(c) : StoredChunk{};  // a new chunk's record: mask 0
  if (before.deflated != deflated) stale_lookup_ = true;  // before the writes: one may fail after the other
  if (before.deflated != deflated && before.bytes == bytes.size())
    check(H5Dwrite_chunk(set_.id(), H5P_DEFAULT, mask, offset.data(), bytes.size() - 1, bytes.data()),
          name_ + ": writing rows");
  check(H5Dwrite_chunk(set_.id(), H5P_DEFAULT, mask, offset.data(), bytes.size(), bytes.data()),
        name_ + ": writing rows");
}

// HDF5 also keeps the record of the chunk it looked up last, and a direct
// write leaves there the mask the chunk had before: after a chunk changed
// form, HDF5's own reading of it (H5Dread, a cut's rewrite) decodes it in
// the other form while the dataset stays open (a cut through a raw chunk
// read it as deflated, or wrote past its buffer). Opened again, HDF5 reads
// each chunk's record from the chunk index; that needs this to be the
// dataset's only open id (HDF5 shares one record among them), as it is.
void RowDataset::open_again() {
  Handle file(H5Iget_file_id(set_.id()), H5Fclose, name_ + ": finding the file");
  std::string path(H5Iget_name(set_.id(), nullptr, 0) + 1, '\0');
  if (path.size() < 2 || H5Iget_name(set_.id(), path.data(), path.size()) < 0)
    throw IoError("HDF5: " + name_ + ": finding the dataset's path failed");
  path.pop_back();
  Handle access(H5Dget_access_plist(set_.id()), H5Pclose, name_ + ": getting the access properties");
  check(set_.close_now(), name_ + ": closing the dataset");
  set_ = Handle(H5Dopen2(file.id(), path.c_str(), access.id()), H5Dclose, name_ + ": opening the dataset again");
  stale_lookup_ = false;
}

void RowDataset::judge_deflate(std::size_t raw_bytes, std::size_t stored_bytes) {
  if (trial_chunks_ == kTrialChunks) return;
  trial_raw_ += raw_bytes;
  trial_stored_ += stored_bytes;
  if (++trial_chunks_ == kTrialChunks)
    deflating_ = static_cast<double>(trial_stored_) < (1.0 - kWorthShrinking) * static_cast<double>(trial_raw_);
}

// Each chunk leaves `held_` as soon as it is stored: a failed store (a full
// disk) leaves the rest held, as they were.
void RowDataset::flush() {
  for (auto at = held_.begin(); at != held_.end();) {
    store(at->first, at->second);
    if (at->second.count < rows_in(at->first)) stored_partly_[at->first] = std::move(at->second.written);
    at = held_.erase(at);
  }
  if (stale_lookup_) open_again();
}

void RowDataset::keep_rows(std::size_t rows) {
  if (rows >= rows_) return;
  const std::size_t chunks = (rows + chunk_rows_ - 1) / chunk_rows_;
  held_.erase(held_.lower_bound(chunks), held_.end());  // wholly past the cut: never stored
  if (rows % chunk_rows_ != 0) {
    cut_chunk_ = rows / chunk_rows_;
    if (stored_[cut_chunk_] && !stored_chunk(cut_chunk_).deflated) held(cut_chunk_);  // flush stores it deflated
  }
  flush();
  h5::keep_rows(set_.id(), rows);
  rows_ = rows;
  stored_.resize(chunks);
  stored_partly_.erase(stored_partly_.lower_bound(chunks), stored_partly_.end());
}

}  // namespace treedyn::h5
