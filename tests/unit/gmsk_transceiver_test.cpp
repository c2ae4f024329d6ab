#include "phy/gmsk_liquid/gmsk_transceiver.hpp"

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

struct Event {
  FrameTag tag;
  std::vector<std::uint8_t> payload;
  bool header_valid = false;
  bool payload_valid = false;
  std::size_t fed = 0;  // samples fed to the receiver up to the end of the reporting chunk
};

class Collector final : public RxHandler {
 public:
  void on_rx(const RxEvent& ev) override {
    events.push_back(Event{
        ev.tag, {ev.payload.begin(), ev.payload.end()}, ev.header_valid, ev.payload_valid, fed});
  }
  std::size_t valid_count() const {
    return static_cast<std::size_t>(std::count_if(events.begin(), events.end(),
                                                  [](const Event& e) { return e.payload_valid; }));
  }
  std::vector<Event> events;
  std::size_t fed = 0;
};

/// Complex AWGN of variance E|n|^2 = variance.
class Awgn {
 public:
  Awgn(std::uint32_t seed, double variance)
      : rng_(seed), dist_(0.0F, static_cast<float>(std::sqrt(variance / 2.0))) {}
  void add(std::span<cf32> x) {
    for (cf32& v : x) v += cf32{dist_(rng_), dist_(rng_)};
  }

 private:
  std::mt19937 rng_;
  std::normal_distribution<float> dist_;
};

std::vector<std::uint8_t> make_payload(std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<std::uint8_t> p(n);
  for (auto& b : p) b = static_cast<std::uint8_t>(rng() & 0xFF);
  return p;
}

/// Runs the TX path in `chunk`-sized calls until the frame of `len` samples is
/// over, checking the per-call contract; returns every sample written (the last
/// chunk zero-padded) and the signal samples reported in `*signal`.
std::vector<cf32> transmit_chunked(Transceiver& tx, std::size_t chunk, std::size_t len,
                                   std::size_t* signal) {
  std::vector<cf32> all;
  std::vector<cf32> buf(chunk);
  *signal = 0;
  while (tx.tx_busy()) {
    std::fill(buf.begin(), buf.end(), cf32{7.0F, -7.0F});  // garbage that must be overwritten
    const std::size_t n = tx.transmit(buf);
    EXPECT_LE(n, chunk);
    const auto zeros = std::count(buf.begin() + static_cast<std::ptrdiff_t>(n), buf.end(), cf32{});
    EXPECT_EQ(static_cast<std::size_t>(zeros), chunk - n) << "tail of a chunk not zero-filled";
    *signal += n;
    EXPECT_EQ(tx.tx_busy(), *signal < len) << "after " << *signal << " of " << len;
    all.insert(all.end(), buf.begin(), buf.end());
    if (all.size() > 10'000'000) break;  // never loop forever on a broken TX path
  }
  return all;
}

void receive_chunked(Transceiver& rx, std::span<const cf32> x, std::size_t chunk, Collector& c) {
  for (std::size_t off = 0; off < x.size(); off += chunk) {
    const std::size_t len = std::min(chunk, x.size() - off);
    c.fed = off + len;
    rx.receive(x.subspan(off, len), c);
  }
}

std::unique_ptr<Transceiver> make_default() {
  return make_gmsk_transceiver(GmskSettings{});
}

double mean_power(std::span<const cf32> x) {
  double p = 0.0;
  for (const cf32& v : x) p += std::norm(v);
  return x.empty() ? 0.0 : p / static_cast<double>(x.size());
}

void expect_chunked_round_trip(std::size_t tx_chunk, std::size_t rx_chunk) {
  auto tx = make_default();
  auto rx = make_default();
  const FrameTag tag{3, 7, 0xA1B2C3D4U};
  const auto payload = make_payload(80, 42);
  EXPECT_FALSE(tx->tx_busy());
  const std::size_t len = tx->start_frame(tag, payload);
  EXPECT_EQ(len, tx->frame_samples(payload.size()));
  EXPECT_TRUE(tx->tx_busy());
  std::size_t signal = 0;
  std::vector<cf32> air(300, cf32{});  // silence before the frame
  const auto frame = transmit_chunked(*tx, tx_chunk, len, &signal);
  air.insert(air.end(), frame.begin(), frame.end());
  air.resize(air.size() + 2000, cf32{});  // and after
  EXPECT_EQ(signal, len);
  EXPECT_FALSE(tx->tx_busy());
  Awgn noise(7, 0.01);  // 20 dB per-sample SNR
  noise.add(air);
  Collector c;
  receive_chunked(*rx, air, rx_chunk, c);
  ASSERT_EQ(c.events.size(), 1U);
  const Event& e = c.events.front();
  EXPECT_TRUE(e.header_valid);
  EXPECT_TRUE(e.payload_valid);
  EXPECT_EQ(e.tag.src, tag.src);
  EXPECT_EQ(e.tag.dst, tag.dst);
  EXPECT_EQ(e.tag.serial, tag.serial);
  EXPECT_EQ(e.payload, payload);
}

TEST(GmskTransceiver, FrameSentInTickChunksOf1000DecodesExactTagAndPayload) {
  expect_chunked_round_trip(1000, 1000);
}

TEST(GmskTransceiver, FrameSentInOddChunksOf333DecodesExactTagAndPayload) {
  expect_chunked_round_trip(333, 333);
  expect_chunked_round_trip(333, 1000);
}

TEST(GmskTransceiver, TransmitReturnsSignalCountAndZeroFillsOnceFrameIsOver) {
  auto tx = make_default();
  const auto payload = make_payload(20, 1);
  const std::size_t len = tx->start_frame(FrameTag{1, 2, 3}, payload);
  std::vector<cf32> buf(len + 500, cf32{5.0F, 5.0F});
  EXPECT_EQ(tx->transmit(buf), len);
  EXPECT_FALSE(tx->tx_busy());
  EXPECT_GT(mean_power(std::span(buf).first(len)), 0.5);  // constant-envelope GMSK, |x| ~ 1
  EXPECT_EQ(std::count(buf.begin() + static_cast<std::ptrdiff_t>(len), buf.end(), cf32{}), 500);
  std::vector<cf32> idle(100, cf32{1.0F, 1.0F});
  EXPECT_EQ(tx->transmit(idle), 0U);
  EXPECT_EQ(std::count(idle.begin(), idle.end(), cf32{}), 100);
}

TEST(GmskTransceiver, TxBusyHoldsUntilLastSignalSampleIsWritten) {
  auto tx = make_default();
  EXPECT_FALSE(tx->tx_busy());
  const std::size_t len = tx->start_frame(FrameTag{1, 2, 3}, make_payload(10, 2));
  std::vector<cf32> buf(len - 1);
  EXPECT_EQ(tx->transmit(buf), len - 1);
  EXPECT_TRUE(tx->tx_busy());
  std::vector<cf32> one(1);
  EXPECT_EQ(tx->transmit(one), 1U);
  EXPECT_FALSE(tx->tx_busy());
  // Ready for the next frame.
  EXPECT_EQ(tx->start_frame(FrameTag{1, 2, 4}, make_payload(10, 3)), len);
  EXPECT_TRUE(tx->tx_busy());
}

TEST(GmskTransceiver, FrameSamplesDuringTransmissionDoesNotDisturbTheFrame) {
  auto tx = make_default();
  auto rx = make_default();
  const auto payload = make_payload(60, 9);
  const std::size_t len = tx->start_frame(FrameTag{4, 5, 6}, payload);
  std::vector<cf32> air(len + 2000, cf32{});
  tx->transmit(std::span(air).first(len / 2));
  EXPECT_GT(tx->frame_samples(700), len);  // sizes another frame mid-transmission
  tx->transmit(std::span(air).subspan(len / 2));
  Collector c;
  receive_chunked(*rx, air, 1000, c);
  ASSERT_EQ(c.valid_count(), 1U);
  EXPECT_EQ(c.events.front().payload, payload);
}

TEST(GmskTransceiver, CorruptedPayloadGivesNoPayloadValidEvent) {
  auto tx = make_default();
  auto rx = make_default();
  const auto payload = make_payload(80, 5);
  const std::size_t len = tx->start_frame(FrameTag{1, 2, 9}, payload);
  const std::size_t payload_part = tx->frame_samples(80) - tx->frame_samples(0);
  std::vector<cf32> air(200 + len + 2000, cf32{});
  tx->transmit(std::span(air).subspan(200, len));
  // Flip the sign of 64 samples in the middle of the payload part.
  const std::size_t mid = 200 + len - payload_part / 2;
  for (std::size_t i = mid; i < mid + 64; ++i) air[i] = -air[i];
  Awgn noise(11, 0.01);
  noise.add(air);
  Collector c;
  receive_chunked(*rx, air, 1000, c);
  EXPECT_EQ(c.valid_count(), 0U);
  ASSERT_EQ(c.events.size(), 1U);  // the header still decodes: a CRC failure, not a miss
  EXPECT_TRUE(c.events.front().header_valid);
  EXPECT_EQ(c.events.front().tag.serial, 9U);
}

TEST(GmskTransceiver, FrameSamplesGrowBy8kSamplesPerPayloadByte) {
  auto k2 = make_default();
  EXPECT_LT(k2->frame_samples(0), k2->frame_samples(1));
  EXPECT_LT(k2->frame_samples(80), k2->frame_samples(200));
  EXPECT_EQ(k2->frame_samples(81) - k2->frame_samples(80), 16U);
  EXPECT_EQ(k2->frame_samples(2048) - k2->frame_samples(0), 2048U * 16U);
  auto k4 = make_gmsk_transceiver(GmskSettings{4, 3, 0.5F, 2048});
  EXPECT_EQ(k4->frame_samples(81) - k4->frame_samples(80), 32U);
}

TEST(GmskTransceiver, MaxPayloadIsTheConfiguredLimitAndAFullFrameDecodes) {
  EXPECT_EQ(make_default()->max_payload(), 2048U);
  auto tx = make_gmsk_transceiver(GmskSettings{2, 3, 0.5F, 300});
  auto rx = make_gmsk_transceiver(GmskSettings{2, 3, 0.5F, 300});
  EXPECT_EQ(tx->max_payload(), 300U);
  const auto payload = make_payload(300, 8);
  const std::size_t len = tx->start_frame(FrameTag{9, 255, 1}, payload);
  std::vector<cf32> air(len + 2000, cf32{});
  tx->transmit(air);
  Collector c;
  receive_chunked(*rx, air, 1000, c);
  ASSERT_EQ(c.valid_count(), 1U);
  EXPECT_EQ(c.events.front().payload, payload);
  EXPECT_EQ(c.events.front().tag.dst, 255);
  EXPECT_THROW(make_gmsk_transceiver(GmskSettings{2, 3, 0.5F, 70000}), std::invalid_argument);
  EXPECT_THROW(make_gmsk_transceiver(GmskSettings{1, 3, 0.5F, 100}), std::invalid_argument);
}

TEST(GmskTransceiver, EmptyAndOneBytePayloadsRoundTrip) {
  for (const std::size_t n : {0U, 1U}) {
    auto tx = make_default();
    auto rx = make_default();
    const auto payload = make_payload(n, 12);
    const std::size_t len = tx->start_frame(FrameTag{5, 6, 7}, payload);
    std::vector<cf32> air(300 + len + 2000, cf32{});
    tx->transmit(std::span(air).subspan(300, len));
    Collector c;
    receive_chunked(*rx, air, 1000, c);
    ASSERT_EQ(c.valid_count(), 1U) << n << " bytes";
    EXPECT_EQ(c.events.front().payload, payload);
  }
}

TEST(GmskTransceiver, DecodeIsReportedWithinFrameSamplesPlusRxLatency) {
  auto tx = make_default();
  auto rx = make_default();
  const std::size_t start = 500;
  const std::size_t len = tx->start_frame(FrameTag{1, 2, 77}, make_payload(80, 6));
  std::vector<cf32> air(start + len + 4000, cf32{});
  tx->transmit(std::span(air).subspan(start, len));
  Awgn noise(3, 0.01);
  noise.add(air);
  Collector c;
  receive_chunked(*rx, air, 1, c);  // one sample at a time: `fed` is the exact sample
  ASSERT_EQ(c.valid_count(), 1U);
  EXPECT_LE(c.events.front().fed, start + len + rx->rx_latency_samples());
  // ...and not before the frame's last samples reached the receiver.
  EXPECT_GE(c.events.front().fed, start + len - rx->rx_latency_samples());
}

/// Fraction of `frames` 80-byte frames decoded at `snr_db` per-sample SNR.
double packet_success_rate(double snr_db, int frames, std::uint32_t seed) {
  auto tx = make_default();
  auto rx = make_default();
  Collector c;
  std::mt19937 rng(seed);
  int ok = 0;
  for (int f = 0; f < frames; ++f) {
    const auto serial = static_cast<std::uint32_t>(f);
    const auto payload = make_payload(80, static_cast<std::uint32_t>(rng()));
    const std::size_t len = tx->start_frame(FrameTag{1, 2, serial}, payload);
    std::vector<cf32> air(400 + len + 400, cf32{});
    tx->transmit(std::span(air).subspan(400, len));
    const double signal_power = mean_power(std::span(air).subspan(400, len));
    Awgn noise(static_cast<std::uint32_t>(rng()), signal_power / std::pow(10.0, snr_db / 10.0));
    noise.add(air);
    c.events.clear();
    receive_chunked(*rx, air, 1000, c);
    ok += static_cast<int>(std::any_of(c.events.begin(), c.events.end(), [&](const Event& e) {
      return e.payload_valid && e.tag.serial == serial && e.payload == payload;
    }));
  }
  return static_cast<double>(ok) / frames;
}

TEST(GmskTransceiver, SensitivityClaimHoldsAbove90PercentAt14dBAndBelow10PercentAt4dB) {
  EXPECT_DOUBLE_EQ(make_default()->sensitivity_snr_db(), 10.0);
  EXPECT_GE(packet_success_rate(14.0, 50, 1234), 0.9);
  EXPECT_LE(packet_success_rate(4.0, 50, 5678), 0.1);
}

}  // namespace
}  // namespace rfsitl::phy
