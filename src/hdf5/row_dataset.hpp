// A dataset of per-sample rows of one fixed-size number type, filled as the
// records arrive (any order, any batches): each chunk is assembled here and,
// when its last row is in, compressed by libdeflate (deflate.hpp) where
// that pays, and stored whole with H5Dwrite_chunk, HDF5's direct chunk
// write. A chunk stored earlier, with rows missing (too many waiting, or a
// flush), is read back when they come.
//
// Why: rank 0 writes every rank's records while it runs samples of its
// own. Through H5Dwrite, HDF5 compressed each chunk with zlib, and again
// each time a chunk left its cache with rows still to come; the selection
// and the cache cost on top. Readers see an ordinary deflated dataset,
// some of whose chunks may be raw (deflating()).
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "hdf5/hdf5.hpp"

namespace treedyn::h5 {

class RowDataset {
 public:
  RowDataset() = default;
  // Creates (rows, row_shape...) of `type` (a native number type) in
  // `parent`, as create_rows (hdf5.hpp) does.
  RowDataset(hid_t parent, const std::string& name, hid_t type, std::size_t rows, std::span<const hsize_t> row_shape,
             std::size_t chunk_rows = 0, const void* fill = nullptr);
  hid_t id() const { return set_.id(); }
  bool exists() const { return set_.id() != H5I_INVALID_HID; }

  // Rows first_row .. first_row + rows - 1, their values contiguous.
  void write(std::size_t first_row, std::size_t rows, const void* data);
  // Chunk c whole, as a sender assembled it (unit_chunks.hpp): `bytes` are
  // its chunk_rows() rows, deflated or raw, stored as they are. A chunk
  // that already has rows here (never, when every unit is a whole chunk no
  // one else writes to) is decoded and written as rows.
  void write_chunk_whole(std::size_t c, std::span<const unsigned char> bytes, bool deflated);
  std::size_t chunk_rows() const { return chunk_rows_; }

  // Every chunk still missing rows into the file, those rows as the fill:
  // before the file is completed, and before HDF5 reads the dataset (its
  // record of a raw chunk is right from then on; id() may change). A row
  // written later still lands.
  void flush();
  // Keeps rows 0 .. rows-1 (a run that ended early); flushes first.
  void keep_rows(std::size_t rows);

  // Chunks held at most, their rows still arriving (other ranks' samples in
  // flight): beyond that the one written longest ago is stored as it is and
  // read back when its rows come. HDF5's cache held as many.
  static constexpr std::size_t kHeldChunks = 4;
  std::size_t chunks_held() const { return held_.size(); }
  // Chunks stored so far (each once when rows come in order).
  std::size_t chunks_stored() const { return stores_; }

  // Whether deflate pays on this dataset, judged on its first kTrialChunks
  // whole chunks: where together they shrank by less than kWorthShrinking,
  // later whole chunks are stored raw, deflate skipped in their filter mask
  // (bit 0, which HDF5 sets where an optional filter fails); readers built
  // on the HDF5 library honour it. Such rows are random numbers: inputs,
  // final states, extremes, which deflate barely shrinks at a large share
  // of rank 0's deflate time (BENCHMARKS.md, "Rows deflate cannot shrink").
  static constexpr std::size_t kTrialChunks = 4;
  static constexpr double kWorthShrinking = 0.10;
  bool deflating() const { return deflating_; }

 private:
  struct Chunk {
    std::vector<unsigned char> bytes;  // chunk_rows_ rows, the fill where none was written
    std::vector<bool> written;         // which of its rows were
    std::size_t count = 0;             // how many
    std::uint64_t last_write = 0;      // when, in writes to this dataset
  };
  struct StoredChunk {
    std::vector<hsize_t> offset;
    hsize_t bytes = 0;
    bool deflated = true;
  };
  std::size_t rows_in(std::size_t c) const;
  std::vector<hsize_t> chunk_offset(std::size_t c) const;
  StoredChunk stored_chunk(std::size_t c) const;
  Chunk& held(std::size_t c);
  bool all_fill(const std::vector<unsigned char>& bytes) const;
  Chunk load(std::size_t c);
  void store(std::size_t c, const Chunk& chunk);
  void write_chunk(std::size_t c, std::span<const unsigned char> bytes, bool deflated);
  void open_again();
  void judge_deflate(std::size_t raw_bytes, std::size_t stored_bytes);
  void store_least_recent();

  std::string name_;
  Handle set_;
  std::size_t rows_ = 0, row_bytes_ = 0, chunk_rows_ = 1, rank_ = 1;
  std::vector<unsigned char> fill_row_;
  std::map<std::size_t, Chunk> held_;                       // by chunk index
  std::map<std::size_t, std::vector<bool>> stored_partly_;  // stored with rows missing: which were written
  std::vector<bool> stored_;                                // by chunk index
  std::vector<unsigned char> stream_;                       // the compressed chunk, reused
  // A chunk of nothing but the fill, deflated once: the datasets of a
  // column that never moves (a fixed base's position, its extremes) are
  // such chunks throughout (BENCHMARKS.md, "A run's fixed costs").
  std::vector<unsigned char> fill_stream_;
  std::uint64_t writes_ = 0;
  std::size_t stores_ = 0;
  bool deflating_ = true;
  std::size_t trial_chunks_ = 0;  // whole chunks judged so far, at most kTrialChunks
  std::uint64_t trial_raw_ = 0, trial_stored_ = 0;
  std::size_t cut_chunk_ = SIZE_MAX;  // the chunk the last cut went through: always deflated
  bool stale_lookup_ = false;         // a chunk stored in another form than HDF5's record (a new raw one too)
};

}  // namespace treedyn::h5
