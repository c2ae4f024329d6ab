#include "phy/gmsk/fast_gmsk_transceiver.hpp"
#include "fast_gmsk_test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace rfsitl::phy {
namespace {

using namespace fast_gmsk_test;

void expect_exact_decode(unsigned k, std::size_t payload_bytes, std::size_t chunk) {
  SCOPED_TRACE("k=" + std::to_string(k) + " payload=" + std::to_string(payload_bytes) +
               " chunk=" + std::to_string(chunk));
  auto tx = make(k);
  auto rx = make(k);
  const FrameTag tag{3, 7, 0xA1B2C3D4U};
  const auto payload = make_payload(payload_bytes, 42);
  std::vector<cf32> air(321);
  const std::size_t len = put_frame(*tx, tag, payload, air, 321);
  air.resize(321 + len + 700);
  add_noise(air, std::pow(10.0, -1.5), 7 + k);  // 15 dB per-sample SNR
  Collector c;
  receive_chunked(*rx, air, chunk, c);
  expect_decoded(c, tag, payload);
  EXPECT_FALSE(rx->rx_busy());
}

TEST(FastGmskTransceiver, FrameDecodesExactlyAt15dBInTicksOf250AndOddChunksOf333) {
  for (const unsigned k : {2U, 4U}) {
    for (const std::size_t n : {0U, 1U, 80U, 2048U}) {
      expect_exact_decode(k, n, 250);
      expect_exact_decode(k, n, 333);
    }
  }
}

TEST(FastGmskTransceiver, FrameDecodesWithEveryOtherSettingCombination) {
  // k = 8, BT = 0.3, a longer pulse, and a one-sample chunk size.
  for (const auto& s : {FastGmskSettings{8, 0.5F, 3, 100}, FastGmskSettings{2, 0.3F, 4, 100},
                        FastGmskSettings{3, 1.0F, 1, 100}}) {
    auto tx = make_fast_gmsk_transceiver(s);
    auto rx = make_fast_gmsk_transceiver(s);
    const auto payload = make_payload(100, 5);
    std::vector<cf32> air(200);
    const std::size_t len = put_frame(*tx, FrameTag{1, 2, 3}, payload, air, 200);
    air.resize(200 + len + 200);
    add_noise(air, 0.03, 5);
    Collector c;
    receive_chunked(*rx, air, 1, c);
    ASSERT_EQ(c.valid().size(), 1U) << "k=" << s.samples_per_symbol;
    EXPECT_EQ(c.valid().front().payload, payload);
  }
}

TEST(FastGmskTransceiver, TransmitReturnsSignalCountZeroFillsAndHasUnitPower) {
  auto tx = make();
  EXPECT_FALSE(tx->tx_busy());
  const std::size_t len = tx->start_frame(FrameTag{1, 2, 3}, make_payload(80, 1));
  EXPECT_EQ(len, tx->frame_samples(80));
  EXPECT_TRUE(tx->tx_busy());
  std::vector<cf32> first(len - 100, cf32{5.0F, 5.0F});
  EXPECT_EQ(tx->transmit(first), len - 100);
  EXPECT_TRUE(tx->tx_busy());
  std::vector<cf32> rest(250, cf32{5.0F, 5.0F});
  EXPECT_EQ(tx->transmit(rest), 100U);
  EXPECT_FALSE(tx->tx_busy());
  EXPECT_EQ(std::count(rest.begin() + 100, rest.end(), cf32{}), 150);
  double power = 0.0;
  for (const cf32& v : first) power += std::norm(v);
  for (std::size_t i = 0; i < 100; ++i) power += std::norm(rest[i]);
  EXPECT_NEAR(power / static_cast<double>(len), 1.0, 1e-4);
  std::vector<cf32> idle(100, cf32{1.0F, 1.0F});
  EXPECT_EQ(tx->transmit(idle), 0U);
  EXPECT_EQ(std::count(idle.begin(), idle.end(), cf32{}), 100);
}

TEST(FastGmskTransceiver, FrameSamplesEqualsStartFrameAndGrowsByEightSymbolsPerByte) {
  for (const unsigned k : {2U, 4U, 8U}) {
    auto tx = make(k);
    for (const std::size_t n : {0U, 1U, 80U, 2048U}) {
      EXPECT_EQ(tx->start_frame(FrameTag{}, make_payload(n, 1)), tx->frame_samples(n));
      std::vector<cf32> sink(tx->frame_samples(n));
      tx->transmit(sink);
    }
    EXPECT_EQ(tx->frame_samples(81) - tx->frame_samples(80), 8U * k);
  }
  // 64 + 32 + 80 + 8 (80 + 4) + 2 symbols and L - 1 = 2 more for the last pulse.
  EXPECT_EQ(make()->frame_samples(80), 1704U);
}

TEST(FastGmskTransceiver, DecodeIsReportedWithinFrameSamplesPlusRxLatency) {
  for (const unsigned k : {2U, 4U}) {
    auto tx = make(k);
    auto rx = make(k);
    const std::size_t start = 517;
    std::vector<cf32> air(start);
    const std::size_t len = put_frame(*tx, FrameTag{1, 2, 77}, make_payload(80, 6), air, start);
    air.resize(start + len + 3000);
    add_noise(air, 0.03, 3);
    Collector c;
    receive_chunked(*rx, air, 1, c);  // one sample at a time: `fed` is exact
    ASSERT_EQ(c.valid().size(), 1U);
    EXPECT_LE(c.valid().front().fed, start + len + rx->rx_latency_samples());
    EXPECT_GE(c.valid().front().fed, start + len - rx->rx_latency_samples());
  }
}

TEST(FastGmskTransceiver, BackToBackFramesWithShortOrNoGapBothDecode) {
  for (const std::size_t gap : {0U, 10U, 101U}) {
    auto tx = make();
    auto rx = make();
    const auto p1 = make_payload(80, 1);
    const auto p2 = make_payload(33, 2);
    std::vector<cf32> air(250);
    const std::size_t len1 = put_frame(*tx, FrameTag{1, 2, 10}, p1, air, 250, 0.3F);
    put_frame(*tx, FrameTag{4, 2, 11}, p2, air, 250 + len1 + gap, 2.1F);
    air.resize(air.size() + 500);
    add_noise(air, 0.03, 17);
    Collector c;
    receive_chunked(*rx, air, 250, c);
    const auto v = c.valid();
    ASSERT_EQ(v.size(), 2U) << "gap " << gap;
    EXPECT_EQ(v[0].tag.serial, 10U);
    EXPECT_EQ(v[0].payload, p1);
    EXPECT_EQ(v[1].tag.serial, 11U);
    EXPECT_EQ(v[1].payload, p2);
  }
}

TEST(FastGmskTransceiver, CorruptedPayloadGivesHeaderValidButPayloadInvalid) {
  auto tx = make();
  auto rx = make();
  std::vector<cf32> air(200);
  const std::size_t len = put_frame(*tx, FrameTag{1, 2, 9}, make_payload(80, 5), air, 200);
  air.resize(200 + len + 500);
  // Flip the sign of 40 samples in the middle of the payload.
  const std::size_t mid = 200 + len - tx->frame_samples(80) / 4;
  for (std::size_t i = mid; i < mid + 40; ++i) air[i] = -air[i];
  add_noise(air, 0.01, 11);
  Collector c;
  receive_chunked(*rx, air, 250, c);
  ASSERT_EQ(c.events.size(), 1U);
  EXPECT_TRUE(c.events.front().header_valid);
  EXPECT_FALSE(c.events.front().payload_valid);
  EXPECT_EQ(c.events.front().tag.serial, 9U);
}

TEST(FastGmskTransceiver, RxBusyRisesInsideAFrameAndFallsWithTheDecode) {
  auto tx = make();
  auto rx = make();
  std::vector<cf32> air(1000);
  const std::size_t len = put_frame(*tx, FrameTag{1, 2, 5}, make_payload(80, 3), air, 1000);
  air.resize(1000 + len + 1000);
  add_noise(air, 0.01, 4);
  Collector c;
  EXPECT_FALSE(rx->rx_busy());
  std::size_t first_busy = 0;
  std::size_t last_busy = 0;
  for (std::size_t off = 0; off < air.size(); off += 50) {
    c.fed = off + 50;
    rx->receive(std::span(air).subspan(off, 50), c);
    if (rx->rx_busy()) {
      if (first_busy == 0) first_busy = off + 50;
      last_busy = off + 50;
    }
  }
  ASSERT_EQ(c.valid().size(), 1U);
  EXPECT_FALSE(rx->rx_busy());
  EXPECT_GT(first_busy, 1000U);                 // not before the frame
  EXPECT_LT(first_busy, 1000U + 2U * 64U);      // within the preamble
  EXPECT_LT(last_busy, c.valid().front().fed);  // idle again once it was reported
  EXPECT_GE(last_busy + 50, 1000U + len - 2U * 4U);
}

TEST(FastGmskTransceiver, ResetReceiverAbandonsAFrameAndTheNextOneStillDecodes) {
  auto tx = make();
  auto rx = make();
  std::vector<cf32> air(100);
  const std::size_t len = put_frame(*tx, FrameTag{1, 2, 1}, make_payload(80, 3), air, 100);
  put_frame(*tx, FrameTag{1, 2, 2}, make_payload(80, 4), air, 100 + len + 50);
  air.resize(air.size() + 300);
  add_noise(air, 0.01, 8);
  Collector c;
  receive_chunked(*rx, std::span(air).first(100 + len / 2), 250, c);
  EXPECT_TRUE(rx->rx_busy());
  rx->reset_receiver();
  EXPECT_FALSE(rx->rx_busy());
  receive_chunked(*rx, std::span(air).subspan(100 + len / 2), 250, c);
  ASSERT_EQ(c.valid().size(), 1U);
  EXPECT_EQ(c.valid().front().tag.serial, 2U);
}

TEST(FastGmskTransceiver, OversizedFrameIsReportedAsACrcFailureAndNotWaitedFor) {
  auto tx = make(2, 2048);
  auto rx = make(2, 100);
  std::vector<cf32> air(100);
  const std::size_t len = put_frame(*tx, FrameTag{1, 2, 3}, make_payload(500, 1), air, 100);
  put_frame(*tx, FrameTag{1, 2, 4}, make_payload(50, 2), air, 100 + len + 40);
  air.resize(air.size() + 300);
  add_noise(air, 0.01, 3);
  Collector c;
  receive_chunked(*rx, air, 250, c);
  ASSERT_EQ(c.events.size(), 2U);
  EXPECT_TRUE(c.events[0].header_valid);
  EXPECT_FALSE(c.events[0].payload_valid);
  EXPECT_EQ(c.events[0].tag.serial, 3U);
  EXPECT_TRUE(c.events[1].payload_valid);
  EXPECT_EQ(c.events[1].tag.serial, 4U);
}

TEST(FastGmskTransceiver, InvalidSettingsThrowNamingTheField) {
  const auto message = [](const FastGmskSettings& s) {
    try {
      make_fast_gmsk_transceiver(s);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  EXPECT_NE(message({1, 0.5F, 3, 100}).find("samples_per_symbol"), std::string::npos);
  EXPECT_NE(message({9, 0.5F, 3, 100}).find("samples_per_symbol"), std::string::npos);
  EXPECT_NE(message({2, 0.0F, 3, 100}).find("bandwidth_time"), std::string::npos);
  EXPECT_NE(message({2, 1.5F, 3, 100}).find("bandwidth_time"), std::string::npos);
  EXPECT_NE(message({2, 0.5F, 0, 100}).find("filter_span_symbols"), std::string::npos);
  EXPECT_NE(message({2, 0.5F, 9, 100}).find("filter_span_symbols"), std::string::npos);
  EXPECT_NE(message({2, 0.5F, 3, 0}).find("max_payload_bytes"), std::string::npos);
  EXPECT_NE(message({2, 0.5F, 3, 65536}).find("max_payload_bytes"), std::string::npos);
  EXPECT_EQ(make(8, 65535)->max_payload(), 65535U);
  EXPECT_THROW(make(2, 100)->start_frame(FrameTag{}, make_payload(101, 1)), std::invalid_argument);
}

}  // namespace
}  // namespace rfsitl::phy
