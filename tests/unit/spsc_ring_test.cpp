#include "rfsitl/common/spsc_ring.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace rfsitl {
namespace {

TEST(SpscRing, PopsInPushOrderAndEmptyGivesNullopt) {
  SpscRing<int> ring(4);
  EXPECT_FALSE(ring.try_pop().has_value());
  for (int v : {10, 20, 30}) EXPECT_TRUE(ring.try_push(v));
  EXPECT_EQ(ring.size(), 3U);
  EXPECT_EQ(ring.try_pop(), 10);
  EXPECT_EQ(ring.try_pop(), 20);
  EXPECT_EQ(ring.try_pop(), 30);
  EXPECT_FALSE(ring.try_pop().has_value());
  EXPECT_EQ(ring.size(), 0U);
}

TEST(SpscRing, HoldsExactlyCapacityItems) {
  for (std::size_t cap : {1U, 2U, 7U}) {
    SpscRing<int> ring(cap);
    EXPECT_EQ(ring.capacity(), cap);
    for (std::size_t i = 0; i < cap; ++i) {
      int v = static_cast<int>(i);
      EXPECT_TRUE(ring.try_push(v)) << "cap " << cap << " item " << i;
    }
    int extra = -1;
    EXPECT_FALSE(ring.try_push(extra)) << "cap " << cap;
    EXPECT_EQ(ring.size(), cap);
    EXPECT_EQ(ring.try_pop(), 0);
    EXPECT_TRUE(ring.try_push(extra));  // one slot freed
    EXPECT_EQ(ring.size(), cap);
  }
}

TEST(SpscRing, FailedPushLeavesTheItemWithTheCaller) {
  SpscRing<std::unique_ptr<std::string>> ring(1);
  auto first = std::make_unique<std::string>("first");
  ASSERT_TRUE(ring.try_push(first));
  auto second = std::make_unique<std::string>("second");
  EXPECT_FALSE(ring.try_push(second));
  ASSERT_NE(second, nullptr);
  EXPECT_EQ(*second, "second");
  auto popped = ring.try_pop();
  ASSERT_TRUE(popped.has_value());
  EXPECT_EQ(**popped, "first");
  EXPECT_TRUE(ring.try_push(second));
  EXPECT_EQ(second, nullptr);  // moved into the ring on success
  EXPECT_EQ(**ring.try_pop(), "second");
}

TEST(SpscRing, WrapsAroundManyTimesKeepingOrder) {
  SpscRing<std::vector<int>> ring(3);
  int next_in = 0;
  int next_out = 0;
  for (int round = 0; round < 1000; ++round) {
    const int burst = 1 + round % 3;
    for (int i = 0; i < burst; ++i) {
      std::vector<int> v{next_in, -next_in};
      ASSERT_TRUE(ring.try_push(v));
      ++next_in;
    }
    for (int i = 0; i < burst; ++i) {
      const auto v = ring.try_pop();
      ASSERT_TRUE(v.has_value());
      EXPECT_EQ(*v, (std::vector<int>{next_out, -next_out}));
      ++next_out;
    }
  }
  EXPECT_EQ(next_out, next_in);
  EXPECT_EQ(ring.size(), 0U);
}

TEST(SpscRing, TwoThreadsTransfer100kIntegersInOrderWithoutLossOrDuplicates) {
  constexpr std::uint64_t kCount = 100'000;
  SpscRing<std::uint64_t> ring(16);  // small: producer and consumer often meet full / empty
  std::uint64_t refused = 0;
  std::thread producer([&] {
    for (std::uint64_t i = 0; i < kCount; ++i) {
      std::uint64_t v = i;
      while (!ring.try_push(v)) {
        EXPECT_EQ(v, i);  // a refused push keeps the item
        ++refused;
        std::this_thread::yield();
      }
    }
  });
  std::uint64_t expected = 0;
  std::uint64_t out_of_order = 0;
  while (expected < kCount) {
    if (auto v = ring.try_pop()) {
      if (*v != expected) ++out_of_order;
      ++expected;
    } else {
      std::this_thread::yield();
    }
  }
  producer.join();
  EXPECT_EQ(out_of_order, 0U);
  EXPECT_EQ(expected, kCount);
  EXPECT_FALSE(ring.try_pop().has_value());  // nothing extra
  RecordProperty("refused_pushes", std::to_string(refused));
}

}  // namespace
}  // namespace rfsitl
