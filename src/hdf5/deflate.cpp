#include "hdf5/deflate.hpp"

#include <libdeflate.h>

#include <array>
#include <memory>
#include <new>
#include <string>

#include "hdf5/hdf5.hpp"

namespace treedyn::h5 {
namespace {

struct FreeCompressor {
  void operator()(libdeflate_compressor* c) const { libdeflate_free_compressor(c); }
};
struct FreeDecompressor {
  void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
};

// One coder per level, made when first used and kept: making one allocates
// its tables (up to about 1 MB), too much to do for every chunk. Per thread,
// as libdeflate asks.
libdeflate_compressor& compressor(unsigned level) {
  thread_local std::array<std::unique_ptr<libdeflate_compressor, FreeCompressor>, 10> by_level;
  if (level >= by_level.size()) throw IoError("deflate level " + std::to_string(level) + ": 0-9 only");
  auto& c = by_level[level];
  if (!c) c.reset(libdeflate_alloc_compressor(static_cast<int>(level)));
  if (!c) throw std::bad_alloc();
  return *c;
}

libdeflate_decompressor& decompressor() {
  thread_local std::unique_ptr<libdeflate_decompressor, FreeDecompressor> d(libdeflate_alloc_decompressor());
  if (!d) throw std::bad_alloc();
  return *d;
}

}  // namespace

void deflate(std::span<const unsigned char> bytes, unsigned level, std::vector<unsigned char>& stream) {
  libdeflate_compressor& c = compressor(level);
  stream.resize(libdeflate_zlib_compress_bound(&c, bytes.size()));
  const std::size_t written = libdeflate_zlib_compress(&c, bytes.data(), bytes.size(), stream.data(), stream.size());
  // 0 is "did not fit", which the bound rules out: an empty stream must
  // never reach a file as a chunk.
  if (written == 0) throw IoError("deflate: libdeflate found no room within its own bound");
  stream.resize(written);
}

void inflate(std::span<const unsigned char> stream, std::span<unsigned char> bytes, const char* what) {
  std::size_t decoded = 0;
  const libdeflate_result result =
      libdeflate_zlib_decompress(&decompressor(), stream.data(), stream.size(), bytes.data(), bytes.size(), &decoded);
  if (result != LIBDEFLATE_SUCCESS || decoded != bytes.size())
    throw IoError(std::string(what) + ": a stored chunk is not a deflate stream of " + std::to_string(bytes.size()) +
                  " bytes (libdeflate result " + std::to_string(static_cast<int>(result)) + ", " +
                  std::to_string(decoded) + " bytes)");
}

}  // namespace treedyn::h5
