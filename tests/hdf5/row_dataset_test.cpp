// RowDataset assembles chunks of rows arriving in any order and stores each
// with H5Dwrite_chunk, compressed by libdeflate where that pays, raw (deflate
// skipped in the chunk's filter mask) where it does not. Read back here through
// HDF5's own deflate filter (zlib), and chunk by chunk with zlib's
// `uncompress`: what h5py, MATLAB and h5dump do.
#include "hdf5/row_dataset.hpp"

#include <gtest/gtest.h>
#include <sys/mount.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

#include "hdf5/deflate.hpp"
#include "support/command.hpp"

namespace treedyn {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kColumns = 3, kChunkRows = 64;
constexpr double kFill = -7.5;  // what a row never written reads as

// Row r: a smooth column, a noisy one, a constant (rows like the per-sample ones).
std::vector<double> row_values(std::size_t first, std::size_t rows) {
  std::vector<double> v;
  for (std::size_t r = first; r < first + rows; ++r) {
    v.push_back(std::sin(0.01 * static_cast<double>(r)));
    v.push_back(static_cast<double>((r * 2654435761u) % 1000003) / 1000003.0);
    v.push_back(static_cast<double>(r));
  }
  return v;
}

// Rows of random numbers, like a sample's inputs or final state.
std::vector<double> random_rows(std::size_t rows, unsigned seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<double> values(rows * kColumns);
  for (double& v : values) v = uniform(random);
  return values;
}

// Chunk c as the chunk index records it: filter mask and stored bytes.
struct IndexedChunk {
  unsigned mask = ~0u;
  hsize_t bytes = 0;
};
IndexedChunk indexed_chunk(hid_t set, hsize_t first_row) {
  const hsize_t offset[2] = {first_row, 0};
  IndexedChunk chunk;
  haddr_t address = 0;
  EXPECT_GE(H5Dget_chunk_info_by_coord(set, offset, &chunk.mask, &address, &chunk.bytes), 0);
  return chunk;
}

class RowDatasetTest : public ::testing::Test {
 protected:
  void SetUp() override {
    h5::quiet_errors();
    const fs::path path = dir_.path() / "rows.h5";
    file_ = h5::Handle(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose, "creating");
  }
  void TearDown() override { file_.reset(); }
  // Dataset `name` as a reader sees it once the writer closed the file
  // (HDF5's chunk cache of the writer gone); the writer's sets closed first.
  h5::Handle reopened(const char* name) {
    reopen(H5F_ACC_RDONLY);
    return h5::Handle(H5Dopen2(file_.id(), name, H5P_DEFAULT), H5Dclose, "opening the set");
  }
  void reopen(unsigned access) {
    file_.reset();
    file_ = h5::Handle(H5Fopen((dir_.path() / "rows.h5").c_str(), access, H5P_DEFAULT), H5Fclose, "opening");
  }
  h5::RowDataset make(std::size_t rows, const char* name = "rows") {
    const hsize_t shape[1] = {kColumns};
    return h5::RowDataset(file_.id(), name, H5T_NATIVE_DOUBLE, rows, shape, kChunkRows, &kFill);
  }
  // The whole dataset, read through HDF5 (its deflate filter: zlib).
  static std::vector<double> read_all(hid_t set, std::size_t rows) {
    std::vector<double> v(rows * kColumns, std::numeric_limits<double>::quiet_NaN());
    EXPECT_GE(H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0);
    return v;
  }
  // What rows 0 .. rows-1 hold when `written` ones were written.
  static std::vector<double> expected(std::size_t rows, const std::vector<bool>& written) {
    std::vector<double> v = row_values(0, rows);
    for (std::size_t r = 0; r < rows; ++r)
      if (!written[r]) std::fill_n(v.begin() + static_cast<long>(r * kColumns), kColumns, kFill);
    return v;
  }

  testing::TempDir dir_{"rows"};
  h5::Handle file_;
};

// Blocks of 1-40 rows in a shuffled order (other ranks' blocks arrive late),
// some rows written twice, some never: many chunks wait at once, more than
// are held (memory stays bounded), so some are stored with rows missing and
// read back later.
TEST_F(RowDatasetTest, RowsInAnyOrderReadBackAsWritten) {
  const std::size_t rows = 2000;
  h5::RowDataset set = make(rows);
  std::vector<std::pair<std::size_t, std::size_t>> blocks;
  std::mt19937 random(2026);
  for (std::size_t first = 0; first < rows;) {
    const std::size_t n = std::min<std::size_t>(1 + random() % 40, rows - first);
    blocks.emplace_back(first, n);
    first += n;
  }
  std::shuffle(blocks.begin(), blocks.end(), random);
  std::vector<bool> written(rows, false);
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const auto [first, n] = blocks[b];
    if (b % 17 == 5) continue;  // never written: reads as the fill
    set.write(first, n, row_values(first, n).data());
    std::fill_n(written.begin() + static_cast<long>(first), n, true);
    if (b % 13 == 0) set.write(first, n, row_values(first, n).data());  // the same rows again
    ASSERT_LE(set.chunks_held(), h5::RowDataset::kHeldChunks);
  }
  set.flush();
  EXPECT_EQ(read_all(set.id(), rows), expected(rows, written));
}

// Rows that come after a flush land too (the chunk is read back, completed
// and stored again).
TEST_F(RowDatasetTest, RowsAfterAFlushLand) {
  const std::size_t rows = 300;
  h5::RowDataset set = make(rows);
  std::vector<bool> written(rows, false);
  for (std::size_t first = 0; first < rows; first += 20) {
    set.write(first, 10, row_values(first, 10).data());
    std::fill_n(written.begin() + static_cast<long>(first), 10, true);
  }
  set.flush();
  EXPECT_EQ(read_all(set.id(), rows), expected(rows, written));
  for (std::size_t first = 10; first < rows; first += 40) {
    set.write(first, 10, row_values(first, 10).data());
    std::fill_n(written.begin() + static_cast<long>(first), 10, true);
  }
  set.flush();
  EXPECT_EQ(read_all(set.id(), rows), expected(rows, written));
}

// Every stored chunk of rows that deflate shrinks, as h5py or MATLAB would
// find it: deflate applied (filter mask 0), smaller than its rows, and zlib's own `uncompress` gives
// its rows back (the last chunk padded with the fill).
TEST_F(RowDatasetTest, EveryStoredChunkIsAZlibStreamOfItsRows) {
  const std::size_t rows = 1000, chunks = (rows + kChunkRows - 1) / kChunkRows;
  h5::RowDataset set = make(rows);
  for (std::size_t first = rows; first > 0;) {  // last rows first
    const std::size_t n = std::min<std::size_t>(first, 37);
    first -= n;
    set.write(first, n, row_values(first, n).data());
  }
  set.flush();
  std::vector<double> padded = row_values(0, rows);
  padded.resize(chunks * kChunkRows * kColumns, kFill);
  for (std::size_t c = 0; c < chunks; ++c) {
    SCOPED_TRACE("chunk " + std::to_string(c));
    const hsize_t offset[2] = {c * kChunkRows, 0};
    const IndexedChunk indexed = indexed_chunk(set.id(), offset[0]);
    EXPECT_EQ(indexed.mask, 0u);  // deflated (the chunk index's record; H5Dread_chunk's may be stale)
    const hsize_t size = indexed.bytes;
    std::vector<unsigned char> stream(size);
    std::uint32_t ignored = 0;
    ASSERT_GE(H5Dread_chunk(set.id(), H5P_DEFAULT, offset, &ignored, stream.data()), 0);
    std::vector<double> decoded(kChunkRows * kColumns);
    uLongf decoded_bytes = decoded.size() * sizeof(double);
    EXPECT_LT(size, decoded_bytes);
    ASSERT_EQ(uncompress(reinterpret_cast<Bytef*>(decoded.data()), &decoded_bytes, stream.data(), size), Z_OK);
    ASSERT_EQ(decoded_bytes, decoded.size() * sizeof(double));
    EXPECT_TRUE(
        std::equal(decoded.begin(), decoded.end(), padded.begin() + static_cast<long>(c * kChunkRows * kColumns)));
  }
}

// Chunks of nothing but the fill (a fixed base's column) are deflated once
// per dataset and stored as that stream: the very bytes deflating each
// would give. A chunk whose rows are the fill but one, first or last, or
// whose rows are all alike but not the fill, is not such a chunk, and
// reads back as written.
TEST_F(RowDatasetTest, ChunksOfNothingButTheFillStoreTheBytesDeflateGives) {
  const std::size_t rows = 6 * kChunkRows;
  std::vector<double> values(rows * kColumns, kFill);
  values[2 * kChunkRows * kColumns] = 1.0;                       // chunk 2's first value
  values[(4 * kChunkRows - 1) * kColumns + kColumns - 1] = 2.0;  // chunk 3's last value
  std::fill(values.begin() + static_cast<long>(5 * kChunkRows * kColumns), values.end(),
            0.5);  // chunk 5: rows alike, not the fill
  h5::RowDataset set = make(rows);
  set.write(0, rows, values.data());
  EXPECT_EQ(read_all(set.id(), rows), values);
  std::vector<unsigned char> fill_stream;
  const std::vector<double> fill_chunk(kChunkRows * kColumns, kFill);
  h5::deflate({reinterpret_cast<const unsigned char*>(fill_chunk.data()), fill_chunk.size() * sizeof(double)},
              h5::kRowsDeflateLevel, fill_stream);
  for (std::size_t c = 0; c < rows / kChunkRows; ++c) {
    SCOPED_TRACE("chunk " + std::to_string(c));
    const hsize_t offset[2] = {c * kChunkRows, 0};
    const IndexedChunk indexed = indexed_chunk(set.id(), offset[0]);
    EXPECT_EQ(indexed.mask, 0u);
    std::vector<unsigned char> stream(indexed.bytes);
    std::uint32_t ignored = 0;
    ASSERT_GE(H5Dread_chunk(set.id(), H5P_DEFAULT, offset, &ignored, stream.data()), 0);
    const std::span<const unsigned char> rows_bytes(
        reinterpret_cast<const unsigned char*>(values.data() + c * kChunkRows * kColumns),
        kChunkRows * kColumns * sizeof(double));
    std::vector<unsigned char> expected;
    h5::deflate(rows_bytes, h5::kRowsDeflateLevel, expected);
    EXPECT_EQ(stream, expected);
    EXPECT_EQ(stream == fill_stream, c != 2 && c != 3 && c != 5);
  }
}

// Rows that deflate barely shrinks: after its first kTrialChunks whole
// chunks the dataset stores the rest as they are, deflate skipped in their
// filter mask, and HDF5's own reading (every reader's) gives the rows back
// once flushed, also where a chunk stored so with rows missing is read
// back and completed after HDF5 read it. Rows that shrink stay deflated.
TEST_F(RowDatasetTest, RowsThatDeflateCannotShrinkAreStoredAsTheyAreAfterTheTrial) {
  const std::size_t rows = 1000, chunks = (rows + kChunkRows - 1) / kChunkRows;
  const std::vector<double> values = random_rows(rows, 17);
  h5::RowDataset set = make(rows);
  const std::size_t late = 9 * kChunkRows + 5;  // a row of chunk 9 that comes after a flush
  for (std::size_t r = 0; r < rows; ++r)
    if (r != late) set.write(r, 1, values.data() + r * kColumns);
  EXPECT_FALSE(set.deflating());
  set.flush();
  const std::size_t raw_bytes = kChunkRows * kColumns * sizeof(double);
  EXPECT_EQ(indexed_chunk(set.id(), 9 * kChunkRows).mask, 0u) << "a row missing: deflated";
  std::vector<double> so_far = values;
  std::fill_n(so_far.begin() + static_cast<long>(late * kColumns), kColumns, kFill);
  EXPECT_EQ(read_all(set.id(), rows), so_far);
  set.write(late, 1, values.data() + late * kColumns);  // HDF5 has chunk 9 in its cache
  set.flush();
  EXPECT_EQ(read_all(set.id(), rows), values);
  for (std::size_t c = 0; c < chunks; ++c) {
    SCOPED_TRACE("chunk " + std::to_string(c));
    const IndexedChunk indexed = indexed_chunk(set.id(), c * kChunkRows);
    const bool trial = c < h5::RowDataset::kTrialChunks, last = c + 1 == chunks;  // 40 of 64 rows
    EXPECT_EQ(indexed.mask, trial || last ? 0u : 1u);
    if (last) {
      EXPECT_LT(indexed.bytes, raw_bytes * 40 / 64 + 64) << "the fill in the last chunk's 24 missing rows shrinks";
    } else if (!trial) {
      EXPECT_EQ(indexed.bytes, raw_bytes);
    }
  }
  h5::RowDataset shrinking = make(rows, "shrinking");
  shrinking.write(0, rows, row_values(0, rows).data());
  EXPECT_TRUE(shrinking.deflating());
}

// A run that stopped early (a stopping rule) is cut through a chunk of a
// dataset that stores chunks as they are: that chunk is stored deflated
// (ACutWhoseRewriteIsTheChunksRawSizeReadsBack says why) and reads back
// from the closed file. The chunk stored whole and raw (the last one
// stored), stored deflated with rows missing, and still held when the cut
// comes.
TEST_F(RowDatasetTest, ACutThroughAChunkStoredAsItIs) {
  const std::size_t rows = 1000;
  const std::vector<double> values = random_rows(rows, 29);
  struct Case {
    const char* name;
    std::size_t written, kept;  // rows 0 .. written-1 come; the cut keeps kept
    bool flush;
  };
  for (const Case& cut :
       {Case{"whole", 640, 600, false}, Case{"rows_missing", 630, 600, true}, Case{"held", 630, 600, false}}) {
    SCOPED_TRACE(cut.name);
    {
      h5::RowDataset set = make(rows, cut.name);
      set.write(0, cut.written, values.data());
      if (cut.flush) set.flush();
      ASSERT_FALSE(set.deflating());
      set.keep_rows(cut.kept);
    }
    {
      const h5::Handle set = reopened(cut.name);
      EXPECT_EQ(indexed_chunk(set.id(), cut.kept / kChunkRows * kChunkRows).mask, 0u);
      EXPECT_EQ(indexed_chunk(set.id(), (cut.kept / kChunkRows - 1) * kChunkRows).mask, 1u);
      const std::vector<double> kept(values.begin(), values.begin() + static_cast<long>(cut.kept * kColumns));
      EXPECT_EQ(read_all(set.id(), cut.kept), kept);
    }
    reopen(H5F_ACC_RDWR);
  }
}

// Byte rows, 1024 a chunk, of random bytes: deflate cannot shrink them.
constexpr std::size_t kByteRows = 1024;
std::vector<unsigned char> random_bytes(std::size_t rows, unsigned seed) {
  std::mt19937 random(seed);
  std::vector<unsigned char> values(rows);
  for (unsigned char& v : values) v = static_cast<unsigned char>(random());
  return values;
}

// Random bytes whose chunk starting at row `first`, with its first k rows
// and the fill (0) after them, `compress` (a chunk's compressed bytes)
// makes exactly the chunk's raw size: the case where HDF5 keeps the old
// mask. Seeds are tried in turn (the sizes depend on the deflate library's
// version); k is 0 where none gives one.
template <class Compress>
std::pair<std::vector<unsigned char>, std::size_t> bytes_compressing_to_raw_size(std::size_t rows, std::size_t first,
                                                                                 Compress compress) {
  std::vector<unsigned char> chunk(kByteRows);
  for (unsigned seed = 41; seed < 41 + 32; ++seed) {
    std::vector<unsigned char> values = random_bytes(rows, seed);
    for (std::size_t k = 1; k <= kByteRows; ++k) {
      std::fill(chunk.begin(), chunk.end(), 0);
      std::copy_n(values.begin() + static_cast<long>(first), k, chunk.begin());
      if (compress(chunk) == kByteRows) return {std::move(values), k};
    }
  }
  return {{}, 0};
}

// HDF5 records a rewritten chunk's filter mask only where its stored size
// changes. A chunk stored deflated during the trial with rows missing is
// completed after the trial chose to store chunks as they are: where its
// deflated size is its raw size, it still reads back as raw.
TEST_F(RowDatasetTest, AChunkThatChangesFormAtTheSameSizeReadsBack) {
  std::vector<unsigned char> stream;
  const auto [values, k] =
      bytes_compressing_to_raw_size(6 * kByteRows, 0, [&](const std::vector<unsigned char>& chunk) {
        h5::deflate(chunk, h5::kRowsDeflateLevel, stream);
        return stream.size();
      });
  ASSERT_NE(k, 0u) << "no first rows of chunk 0 deflate to its raw size";
  const unsigned char fill = 0;
  h5::RowDataset set(file_.id(), "bytes", H5T_NATIVE_UCHAR, values.size(), {}, kByteRows, &fill);
  set.write(0, k, values.data());
  set.flush();
  EXPECT_EQ(indexed_chunk(set.id(), 0).mask, 0u);
  EXPECT_EQ(indexed_chunk(set.id(), 0).bytes, kByteRows);
  set.write(kByteRows, values.size() - kByteRows, values.data() + kByteRows);  // the trial: chunks 1 .. 4
  ASSERT_FALSE(set.deflating());
  set.write(k, kByteRows - k, values.data() + k);  // chunk 0 complete: stored as it is, same size
  set.flush();
  EXPECT_EQ(indexed_chunk(set.id(), 0).mask, 1u);
  std::vector<unsigned char> back(values.size());
  ASSERT_GE(H5Dread(set.id(), H5T_NATIVE_UCHAR, H5S_ALL, H5S_ALL, H5P_DEFAULT, back.data()), 0);
  EXPECT_EQ(back, values);
}

// A cut rewrites the chunk it goes through with HDF5's own deflate filter
// (zlib's compress2), the rows past it the fill: where that rewrite is the
// chunk's raw size, HDF5 would keep a raw chunk's mask on a deflated one.
// Stored deflated before the cut, the chunk reads back right.
TEST_F(RowDatasetTest, ACutWhoseRewriteIsTheChunksRawSizeReadsBack) {
  const std::size_t before = 5 * kByteRows;  // the trial's chunks and one stored raw
  const auto [values, k] =
      bytes_compressing_to_raw_size(7 * kByteRows, before, [](const std::vector<unsigned char>& chunk) {
        uLongf bytes = compressBound(chunk.size());
        std::vector<unsigned char> stream(bytes);
        EXPECT_EQ(compress2(stream.data(), &bytes, chunk.data(), chunk.size(), h5::kRowsDeflateLevel), Z_OK);
        return static_cast<std::size_t>(bytes);
      });
  ASSERT_NE(k, 0u) << "no cut of chunk 5 rewrites it at its raw size";
  {
    const unsigned char fill = 0;
    h5::RowDataset set(file_.id(), "bytes", H5T_NATIVE_UCHAR, values.size(), {}, kByteRows, &fill);
    set.write(0, before + kByteRows, values.data());
    ASSERT_FALSE(set.deflating());
    set.keep_rows(before + k);
  }
  const h5::Handle set = reopened("bytes");
  EXPECT_EQ(indexed_chunk(set.id(), before).mask, 0u);
  std::vector<unsigned char> back(before + k);
  ASSERT_GE(H5Dread(set.id(), H5T_NATIVE_UCHAR, H5S_ALL, H5S_ALL, H5P_DEFAULT, back.data()), 0);
  EXPECT_EQ(back, std::vector<unsigned char>(values.begin(), values.begin() + static_cast<long>(before + k)));
  if (indexed_chunk(set.id(), before).bytes != kByteRows)
    GTEST_SKIP() << "HDF5's deflate is not this zlib: its rewrite is not the raw size, the case was not made";
}

// A run that ended early keeps its first rows; a row held in memory when
// the cut came is in the file.
TEST_F(RowDatasetTest, KeepRowsCutsTheRowsAndKeepsThoseHeld) {
  const std::size_t rows = 500, kept = 230;
  h5::RowDataset set = make(rows);
  std::vector<bool> written(rows, false);
  for (std::size_t first : {0, 64, 128, 200}) {
    set.write(first, 30, row_values(first, 30).data());
    std::fill_n(written.begin() + static_cast<long>(first), 30, true);
  }
  set.keep_rows(kept);
  h5::Handle space(H5Dget_space(set.id()), H5Sclose, "space");
  hsize_t dims[2] = {0, 0};
  ASSERT_EQ(H5Sget_simple_extent_dims(space.id(), dims, nullptr), 2);
  EXPECT_EQ(dims[0], kept);
  written.resize(kept);
  EXPECT_EQ(read_all(set.id(), kept), expected(kept, written));
  EXPECT_THROW(set.write(kept, 1, row_values(kept, 1).data()), h5::IoError);
}

// Rows that come in order: every chunk is compressed and stored once, as
// its last row comes; none is left waiting.
TEST_F(RowDatasetTest, RowsInOrderStoreEachChunkOnce) {
  const std::size_t rows = 1000, chunks = (rows + kChunkRows - 1) / kChunkRows;
  h5::RowDataset set = make(rows);
  for (std::size_t first = 0; first < rows; first += 7) {
    const std::size_t n = std::min<std::size_t>(7, rows - first);
    set.write(first, n, row_values(first, n).data());
  }
  EXPECT_EQ(set.chunks_held(), 0u);
  EXPECT_EQ(set.chunks_stored(), chunks);
  EXPECT_EQ(read_all(set.id(), rows), row_values(0, rows));
}

// /samples/status: int32, one value a row (a rank-1 dataset), rows never
// written read as its fill ("not run", 3), also inside stored chunks.
TEST_F(RowDatasetTest, IntegerRowsOfOneValueWithAFill) {
  const std::int32_t not_run = 3;
  const std::size_t rows = 5000;  // 16384 rows a chunk: one partial chunk
  h5::RowDataset set(file_.id(), "status", H5T_NATIVE_INT32, rows, {}, 0, &not_run);
  std::vector<std::int32_t> expected(rows, not_run);
  for (std::size_t first = 4000; first < rows; first += 25) {
    std::vector<std::int32_t> block(10);
    for (std::size_t k = 0; k < block.size(); ++k)
      block[k] = expected[first + k] = static_cast<std::int32_t>(first + k) % 3;
    set.write(first, block.size(), block.data());
  }
  set.flush();
  std::vector<std::int32_t> back(rows, -1);
  ASSERT_GE(H5Dread(set.id(), H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, back.data()), 0);
  EXPECT_EQ(back, expected);
}

// /trajectories: one (times x columns) row a chunk, stored at its write.
TEST_F(RowDatasetTest, TrajectoryRowsOneAChunk) {
  const hsize_t shape[2] = {5, 2};
  h5::RowDataset set(file_.id(), "trajectory", H5T_NATIVE_DOUBLE, 4, shape, 1);
  std::vector<double> expected(4 * 10, 0.0);  // HDF5's fill: zero
  for (std::size_t row : {3, 0}) {
    const std::size_t stored = set.chunks_stored();
    for (std::size_t k = 0; k < 10; ++k) expected[row * 10 + k] = 0.5 * static_cast<double>(row * 10 + k) + 1.0;
    set.write(row, 1, expected.data() + row * 10);
    EXPECT_EQ(set.chunks_stored(), stored + 1);
    EXPECT_EQ(set.chunks_held(), 0u);
  }
  std::vector<double> back(expected.size(), -1.0);
  ASSERT_GE(H5Dread(set.id(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, back.data()), 0);
  EXPECT_EQ(back, expected);
}

// A cut through a chunk stored with rows missing: HDF5 rewrites that edge
// chunk itself (zlib, through its cache); its last rows, written after,
// read it back from there and complete it.
TEST_F(RowDatasetTest, ACutThroughAChunkStoredWithRowsMissingThenItsLastRows) {
  const std::size_t rows = 500, kept = 230;  // chunk 3 holds rows 192 .. 255, cut to 192 .. 229
  h5::RowDataset set = make(rows);
  std::vector<bool> written(rows, false);
  for (auto [first, n] : {std::pair<std::size_t, std::size_t>{0, 192}, {192, 8}, {300, 20}}) {
    set.write(first, n, row_values(first, n).data());
    std::fill_n(written.begin() + static_cast<long>(first), n, true);
  }
  set.flush();
  set.keep_rows(kept);
  set.write(200, kept - 200, row_values(200, kept - 200).data());
  std::fill_n(written.begin() + 200, kept - 200, true);
  EXPECT_EQ(set.chunks_held(), 0u) << "chunk 3 is complete once cut";
  written.resize(kept);
  EXPECT_EQ(read_all(set.id(), kept), expected(kept, written));
}

// Rows beyond the dataset, and a type whose stored bytes differ from its
// bytes in memory, are refused, not written.
TEST_F(RowDatasetTest, RefusesRowsPastTheEndAndConvertedTypes) {
  h5::RowDataset set = make(100);
  EXPECT_THROW(set.write(95, 6, row_values(95, 6).data()), h5::IoError);
  const hsize_t shape[1] = {kColumns};
  EXPECT_THROW(h5::RowDataset(file_.id(), "big_endian", H5T_STD_I32BE, 10, shape), h5::IoError);
  EXPECT_EQ(H5Lexists(file_.id(), "big_endian", H5P_DEFAULT), 0);
  const hsize_t no_columns[1] = {0};
  EXPECT_THROW(h5::RowDataset(file_.id(), "empty_rows", H5T_NATIVE_DOUBLE, 10, no_columns), h5::IoError);
}

// A chunk stored with rows missing that is no longer a deflate stream when
// its rows come (a damaged file): the write fails with an error that says
// so, not with rows of garbage.
TEST_F(RowDatasetTest, AStoredChunkThatIsNotADeflateStreamFailsTheWrite) {
  h5::RowDataset set = make(200);
  set.write(0, 10, row_values(0, 10).data());
  set.flush();
  const std::vector<unsigned char> garbage(300, 0xA5);
  const hsize_t offset[2] = {0, 0};
  ASSERT_GE(H5Dwrite_chunk(set.id(), H5P_DEFAULT, 0, offset, garbage.size(), garbage.data()), 0);
  try {
    set.write(10, 5, row_values(10, 5).data());
    FAIL() << "no error";
  } catch (const h5::IoError& e) {
    EXPECT_NE(std::string(e.what()).find("rows: reading back chunk 0: a stored chunk is not a deflate stream of "
                                         "1536 bytes"),
              std::string::npos)
        << e.what();
  }
  // Nothing half-made is kept: the next write fails the same way, and the
  // other chunks still take rows.
  EXPECT_THROW(set.write(10, 5, row_values(10, 5).data()), h5::IoError);
  EXPECT_EQ(set.chunks_held(), 0u);
  set.write(64, 64, row_values(64, 64).data());
  std::vector<double> chunk1(64 * kColumns);
  h5::Handle file_space(H5Dget_space(set.id()), H5Sclose, "space");
  const hsize_t start[2] = {64, 0}, count[2] = {64, kColumns};
  ASSERT_GE(H5Sselect_hyperslab(file_space.id(), H5S_SELECT_SET, start, nullptr, count, nullptr), 0);
  h5::Handle memory(H5Screate_simple(2, count, nullptr), H5Sclose, "memory space");
  ASSERT_GE(H5Dread(set.id(), H5T_NATIVE_DOUBLE, memory.id(), file_space.id(), H5P_DEFAULT, chunk1.data()), 0);
  EXPECT_EQ(chunk1, row_values(64, 64));
}

// A full disk while a dataset stores raw chunks: the write fails with the
// dataset's name and the step, no crash and no rows of garbage; the rows
// not stored stay held. Needs root to mount a small tmpfs.
TEST(RowDatasetFullDisk, RawRowsOnAFullDiskFailWithTheDatasetsName) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to mount a small tmpfs";
  h5::quiet_errors();
  testing::TempDir dir{"rows_full"};
  const fs::path disk = dir.path() / "disk";
  fs::create_directory(disk);
  if (mount("tmpfs", disk.c_str(), "tmpfs", 0, "size=128k") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno) << ")";
  const std::size_t rows = 20000;  // 480 KB of rows, raw after the trial's 4 chunks
  const std::vector<double> values = random_rows(rows, 7);
  std::string error;
  bool deflating = true;
  {
    h5::Handle file(H5Fcreate((disk / "rows.h5").c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose,
                    "creating");
    const hsize_t shape[1] = {kColumns};
    h5::RowDataset set(file.id(), "inputs", H5T_NATIVE_DOUBLE, rows, shape, kChunkRows, &kFill);
    try {
      for (std::size_t first = 0; first < rows; first += kChunkRows)
        set.write(first, std::min(kChunkRows, rows - first), values.data() + first * kColumns);
    } catch (const h5::IoError& e) {
      error = e.what();
    }
    deflating = set.deflating();
    EXPECT_EQ(set.chunks_held(), 1u);
  }
  umount(disk.c_str());
  EXPECT_EQ(error, "HDF5: inputs: writing rows failed");
  EXPECT_FALSE(deflating);
}

// The same full disk for chunks a sender assembled (write_chunk_whole, a
// unit's): the store fails with the dataset's name, and the chunk that
// failed is not counted as stored.
TEST(RowDatasetFullDisk, SentChunksOnAFullDiskFailWithTheDatasetsName) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to mount a small tmpfs";
  h5::quiet_errors();
  testing::TempDir dir{"sent_full"};
  const fs::path disk = dir.path() / "disk";
  fs::create_directory(disk);
  if (mount("tmpfs", disk.c_str(), "tmpfs", 0, "size=128k") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno) << ")";
  const std::size_t rows = 20000;
  const std::vector<double> values = random_rows(rows, 8);
  std::string error;
  std::size_t stored = 0, sent = 0;
  {
    h5::Handle file(H5Fcreate((disk / "rows.h5").c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose,
                    "creating");
    const hsize_t shape[1] = {kColumns};
    h5::RowDataset set(file.id(), "inputs", H5T_NATIVE_DOUBLE, rows, shape, kChunkRows, &kFill);
    const std::size_t chunk_bytes = kChunkRows * kColumns * sizeof(double);
    try {
      for (std::size_t c = 0; c < rows / kChunkRows; ++c, ++sent) {
        const auto* bytes = reinterpret_cast<const unsigned char*>(values.data() + c * kChunkRows * kColumns);
        set.write_chunk_whole(c, std::span<const unsigned char>(bytes, chunk_bytes), false);
      }
    } catch (const h5::IoError& e) {
      error = e.what();
    }
    stored = set.chunks_stored();
  }
  umount(disk.c_str());
  EXPECT_EQ(error, "HDF5: inputs: writing rows failed");
  EXPECT_LT(sent, rows / kChunkRows) << "the disk never filled";
  EXPECT_EQ(stored, sent) << "the chunk whose write failed was counted as stored";
}

}  // namespace
}  // namespace treedyn
