#include "common/buffer_pool.hpp"

#include <gtest/gtest.h>

#include <numeric>
#include <random>

namespace treedyn {
namespace {

TEST(BufferPool, AGivenBackBufferIsTakenAgainWithoutAllocating) {
  BufferPool pool(1000);
  ByteBuffer first = pool.take(300);
  ASSERT_NE(first.data, nullptr);
  EXPECT_EQ(first.size, 300u);
  const char* where = first.data.get();
  pool.give_back(std::move(first));
  EXPECT_EQ(pool.kept_bytes(), 300u);
  const ByteBuffer again = pool.take(200);  // fits in the kept one
  EXPECT_EQ(again.data.get(), where);
  EXPECT_EQ(again.size, 300u);
  EXPECT_EQ(pool.kept_bytes(), 0u);
  EXPECT_EQ(pool.take(0).data, nullptr);
}

TEST(BufferPool, TakesTheSmallestThatFitsAndAllocatesWhenNoneDoes) {
  BufferPool pool(1000);
  ByteBuffer small = pool.take(100), middle = pool.take(200), large = pool.take(400);
  const char* middle_at = middle.data.get();
  pool.give_back(std::move(large));
  pool.give_back(std::move(small));
  pool.give_back(std::move(middle));
  EXPECT_EQ(pool.take(150).data.get(), middle_at);
  const ByteBuffer fresh = pool.take(500);  // larger than every kept one: new
  EXPECT_EQ(fresh.size, 500u);
  EXPECT_EQ(pool.kept_buffers(), 2u);
  EXPECT_EQ(pool.kept_bytes(), 500u);
}

TEST(BufferPool, OverItsBoundSmallerBuffersGoFirst) {
  BufferPool pool(1000);
  ByteBuffer a = pool.take(300), b = pool.take(300), c = pool.take(600), d = pool.take(1001), e = pool.take(100);
  pool.give_back(std::move(a));
  pool.give_back(std::move(b));
  pool.give_back(std::move(c));  // 1200 > 1000: one 300 goes
  EXPECT_EQ(pool.kept_bytes(), 900u);
  EXPECT_EQ(pool.kept_buffers(), 2u);
  pool.give_back(std::move(d));  // beyond the bound on its own: freed
  EXPECT_EQ(pool.kept_bytes(), 900u);
  pool.give_back(std::move(e));  // fits exactly
  EXPECT_EQ(pool.kept_bytes(), 1000u);
  ByteBuffer f = pool.take(50);  // the smallest that fits: the 100 one
  EXPECT_EQ(f.size, 100u);
  EXPECT_EQ(pool.kept_bytes(), 900u);
}

// A buffer that would fit only by evicting buffers at least as large is
// freed, and nothing is evicted for it.
TEST(BufferPool, ABufferThatCannotFitIsFreedWithoutEvictingAny) {
  BufferPool pool(1000);
  ByteBuffer a = pool.take(100), b = pool.take(450), c = pool.take(450), d = pool.take(400), e = pool.take(200);
  pool.give_back(std::move(a));
  pool.give_back(std::move(b));
  pool.give_back(std::move(c));
  pool.give_back(std::move(d));  // only the 100 is smaller: 900 + 400 > 1000 even without it
  EXPECT_EQ(pool.kept_bytes(), 1000u);
  EXPECT_EQ(pool.kept_buffers(), 3u);
  EXPECT_EQ(pool.take(100).size, 100u) << "the 100 was evicted for nothing";
  pool.give_back(std::move(e));  // 900 + 200 > 1000, and the 450s are larger: freed
  EXPECT_EQ(pool.kept_bytes(), 900u);
  EXPECT_EQ(pool.kept_buffers(), 2u);
}

// Random takes and returns: every buffer taken is as large as asked, and
// the bound holds.
TEST(BufferPool, KeepsWithinItsBoundUnderRandomUse) {
  BufferPool pool(1 << 16);
  std::mt19937 random(7);
  std::vector<ByteBuffer> held;
  for (int step = 0; step < 20000; ++step) {
    if (held.empty() || random() % 2 == 0) {
      const std::size_t bytes = 1 + random() % (1 << 14);
      held.push_back(pool.take(bytes));
      ASSERT_GE(held.back().size, bytes);
      held.back().data[bytes - 1] = 'x';  // writable to its end
    } else {
      const std::size_t k = random() % held.size();
      pool.give_back(std::move(held[k]));
      held.erase(held.begin() + static_cast<std::ptrdiff_t>(k));
    }
    ASSERT_LE(pool.kept_bytes(), std::size_t{1} << 16);
  }
}

}  // namespace
}  // namespace treedyn
