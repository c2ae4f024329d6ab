// The OFDM transceiver end to end: frames built by its TX path and received by
// another instance's RX path, through noise, carrier offset and multipath.
#include "phy/ofdm/ofdm_transceiver.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "phy/ofdm/mac_frame.hpp"
#include "phy/ofdm/rates.hpp"

namespace rfsitl::phy {
namespace {

struct Collect : RxHandler {
  struct Event {
    FrameTag tag;
    std::vector<std::uint8_t> payload;
    bool valid;
  };
  std::vector<Event> events;
  void on_rx(const RxEvent& ev) override {
    events.push_back({ev.tag, {ev.payload.begin(), ev.payload.end()}, ev.payload_valid});
  }
};

struct Impairments {
  double snr_db = 30.0;
  double cfo_subcarriers = 0.0;       ///< carrier offset in subcarrier spacings (fs / 64)
  std::vector<cf32> taps = {{1, 0}};  ///< multipath channel
  std::uint32_t seed = 1;
};

/// Transmits `payload` through `imp` in 250-sample ticks surrounded by noise.
std::vector<Collect::Event> loopback(unsigned mbps, const std::vector<std::uint8_t>& payload,
                                     const Impairments& imp, std::size_t* frame_len = nullptr) {
  auto tx = make_ofdm_transceiver({mbps, 2048});
  auto rx = make_ofdm_transceiver({mbps, 2048});
  const FrameTag tag{3, 9, 0x01020304U + mbps};
  const std::size_t len = tx->start_frame(tag, payload);
  if (frame_len != nullptr) *frame_len = len;
  std::vector<cf32> air(600 + len + 600, cf32{});
  std::vector<cf32> frame(len);
  EXPECT_EQ(tx->transmit(frame), len);
  for (std::size_t n = 0; n < len; ++n) {
    for (std::size_t t = 0; t < imp.taps.size() && t <= n; ++t) {
      air[600 + n] += imp.taps[t] * frame[n - t];
    }
  }
  std::mt19937 rng(imp.seed);
  const double sigma = std::sqrt(std::pow(10.0, -imp.snr_db / 10.0) / 2.0);
  std::normal_distribution<double> g(0.0, sigma);
  const double w = 2.0 * std::numbers::pi * imp.cfo_subcarriers / 64.0;
  for (std::size_t n = 0; n < air.size(); ++n) {
    const auto rot = std::polar(1.0, w * static_cast<double>(n));
    air[n] = cf32(std::complex<double>(air[n]) * rot) +
             cf32(static_cast<float>(g(rng)), static_cast<float>(g(rng)));
  }
  Collect sink;
  for (std::size_t i = 0; i < air.size(); i += 250) {
    rx->receive(std::span<const cf32>(air).subspan(i, std::min<std::size_t>(250, air.size() - i)),
                sink);
  }
  return sink.events;
}

std::vector<std::uint8_t> test_payload(std::size_t n) {
  std::vector<std::uint8_t> p(n);
  for (std::size_t i = 0; i < n; ++i) p[i] = static_cast<std::uint8_t>(i * 31 + 7);
  return p;
}

TEST(OfdmTransceiver, EveryRateDeliversAnEightyByteFrameExactly) {
  for (const auto& r : ofdm::all_rates()) {
    const auto events = loopback(r.mbps, test_payload(80), {});
    ASSERT_EQ(events.size(), 1U) << r.mbps << " Mbit/s";
    EXPECT_TRUE(events[0].valid) << r.mbps;
    EXPECT_EQ(events[0].tag.src, 3);
    EXPECT_EQ(events[0].tag.dst, 9);
    EXPECT_EQ(events[0].tag.serial, 0x01020304U + r.mbps);
    EXPECT_EQ(events[0].payload, test_payload(80)) << r.mbps;
  }
}

TEST(OfdmTransceiver, FrameLengthFollowsTheStandardSymbolCount) {
  std::size_t len = 0;
  loopback(6, test_payload(80), {}, &len);
  // PSDU = 80 + 30 octets; 6 Mbit/s carries 24 bits per symbol:
  // ceil((16 + 8 * 110 + 6) / 24) = 38 DATA symbols.
  EXPECT_EQ(len, 320U + 80U * (1 + 38));
  EXPECT_EQ(make_ofdm_transceiver({6, 2048})->frame_samples(80), len);
}

TEST(OfdmTransceiver, CopesWithCarrierOffsetOfAFractionOfASubcarrier) {
  for (const double cfo : {-0.4, 0.25, 0.45}) {
    for (unsigned mbps : {6U, 24U, 54U}) {
      Impairments imp;
      imp.cfo_subcarriers = cfo;
      const auto events = loopback(mbps, test_payload(80), imp);
      ASSERT_EQ(events.size(), 1U) << cfo << " " << mbps;
      EXPECT_TRUE(events[0].valid) << "cfo " << cfo << " subcarriers at " << mbps << " Mbit/s";
    }
  }
}

TEST(OfdmTransceiver, CopesWithAShortMultipathChannel) {
  Impairments imp;
  imp.taps = {{0.8F, 0.1F}, {0.0F, 0.45F}, {0.25F, -0.1F}, {0.0F, 0.0F}, {-0.1F, 0.05F}};
  imp.cfo_subcarriers = 0.1;
  for (unsigned mbps : {6U, 12U, 24U, 36U}) {
    const auto events = loopback(mbps, test_payload(80), imp);
    ASSERT_EQ(events.size(), 1U) << mbps;
    EXPECT_TRUE(events[0].valid) << "multipath at " << mbps << " Mbit/s";
  }
}

TEST(OfdmTransceiver, NoiseAloneDecodesNothing) {
  auto rx = make_ofdm_transceiver({6, 2048});
  std::mt19937 rng(5);
  std::normal_distribution<float> g(0.0F, 0.7071F);
  std::vector<cf32> noise(200000);
  for (auto& s : noise) s = {g(rng), g(rng)};
  Collect sink;
  rx->receive(noise, sink);
  for (const auto& e : sink.events) EXPECT_FALSE(e.valid);
  // The detector needs 24 samples in a row that look periodic: rare in noise.
  EXPECT_LE(sink.events.size(), 2U);
}

TEST(OfdmTransceiver, LowSnrFramesFailTheFcsInsteadOfDeliveringGarbage) {
  // 54 Mbit/s needs well over 20 dB; at 8 dB nothing may come out valid.
  for (std::uint32_t seed = 1; seed <= 5; ++seed) {
    Impairments imp;
    imp.snr_db = 8.0;
    imp.seed = seed;
    for (const auto& e : loopback(54, test_payload(80), imp)) EXPECT_FALSE(e.valid);
  }
}

TEST(OfdmTransceiver, OutputHasUnitMeanPower) {
  auto tx = make_ofdm_transceiver({36, 2048});
  const std::size_t len = tx->start_frame({1, 2, 3}, test_payload(200));
  std::vector<cf32> s(len);
  tx->transmit(s);
  double p = 0.0;
  for (const cf32& v : s) p += std::norm(v);
  EXPECT_NEAR(p / static_cast<double>(len), 1.0, 1e-3);
}

TEST(OfdmTransceiver, RejectsRatesOutsideTheStandard) {
  EXPECT_THROW(make_ofdm_transceiver({7, 2048}), std::invalid_argument);
  EXPECT_THROW(make_ofdm_transceiver({6, 5000}), std::invalid_argument);
}

TEST(OfdmMacFrame, RoundTripsTagAndPayloadAndMarksBroadcast) {
  const auto psdu = ofdm::encode_mac_frame({4, kBroadcastId, 0xDEADBEEF}, test_payload(10));
  EXPECT_EQ(psdu.size(), 10 + ofdm::kMacOverheadBytes);
  for (int i = 4; i < 10; ++i) EXPECT_EQ(psdu[i], 0xFF);  // address 1: broadcast
  const auto mac = ofdm::decode_mac_frame(psdu);
  ASSERT_TRUE(mac.has_value());
  EXPECT_EQ(mac->tag.src, 4);
  EXPECT_EQ(mac->tag.dst, kBroadcastId);
  EXPECT_EQ(mac->tag.serial, 0xDEADBEEFU);
  EXPECT_EQ(std::vector<std::uint8_t>(mac->payload.begin(), mac->payload.end()), test_payload(10));
}

}  // namespace
}  // namespace rfsitl::phy
