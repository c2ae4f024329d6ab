#include "phy/gfsk/gfsk_transceiver.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <span>
#include <string>
#include <vector>

// The fast GMSK tests' helpers (collector, noise, payloads, chunked feeding)
// work on any Transceiver.
#include "fast_gmsk_test_support.hpp"

namespace rfsitl::phy {
namespace {

using fast_gmsk_test::add_noise;
using fast_gmsk_test::Collector;
using fast_gmsk_test::Event;
using fast_gmsk_test::expect_decoded;
using fast_gmsk_test::make_payload;
using fast_gmsk_test::receive_chunked;

GfskSettings settings(GfskReceiver r, unsigned k = 8, float h = 2.0F, float bt = 0.5F) {
  GfskSettings s;
  s.receiver = r;
  s.samples_per_symbol = k;
  s.modulation_index = h;
  s.bandwidth_time = bt;
  return s;
}

/// The frame's samples alone.
std::vector<cf32> frame(Transceiver& tx, const FrameTag& tag, std::span<const std::uint8_t> p) {
  std::vector<cf32> f(tx.start_frame(tag, p));
  EXPECT_EQ(tx.transmit(f), f.size());
  return f;
}

/// `lead` samples of silence, the frame rotated by `phase` and frequency
/// shifted by `cfo` cycles per sample, `tail` samples of silence.
std::vector<cf32> on_air(const std::vector<cf32>& f, std::size_t lead, std::size_t tail,
                         float phase, double cfo = 0.0) {
  std::vector<cf32> air(lead + f.size() + tail);
  for (std::size_t i = 0; i < f.size(); ++i) {
    const double turn = phase + 2.0 * 3.14159265358979 * cfo * static_cast<double>(i);
    air[lead + i] = f[i] * std::polar(1.0F, static_cast<float>(turn));
  }
  return air;
}

TEST(GfskTransceiver, LoopbackDecodesBothReceiversAtSeveralRatesAndLengths) {
  struct Case {
    unsigned k;
    float h;
    float bt;
  };
  std::mt19937 rng(11);
  for (const auto r : {GfskReceiver::kDiscriminator, GfskReceiver::kEnergy}) {
    for (const Case c :
         {Case{8, 2.0F, 0.5F}, Case{4, 2.0F, 0.5F}, Case{2, 1.0F, 0.0F}, Case{16, 0.5F, 0.3F}}) {
      for (const std::size_t n : {0U, 1U, 80U, 255U}) {
        SCOPED_TRACE("rx=" + std::to_string(static_cast<int>(r)) + " k=" + std::to_string(c.k) +
                     " n=" + std::to_string(n));
        auto tx = make_gfsk_transceiver(settings(r, c.k, c.h, c.bt));
        auto rx = make_gfsk_transceiver(settings(r, c.k, c.h, c.bt));
        const FrameTag tag{5, 7, static_cast<std::uint32_t>(rng())};
        const auto p = make_payload(n, static_cast<std::uint32_t>(rng()));
        auto air = on_air(frame(*tx, tag, p), 100 + rng() % 300, 300,
                          6.28F * static_cast<float>(rng() % 1000) / 1000);
        add_noise(air, 0.01, static_cast<std::uint32_t>(rng()));  // 20 dB per-sample SNR
        Collector col;
        receive_chunked(*rx, air, 250, col);
        expect_decoded(col, tag, p);
        EXPECT_FALSE(rx->rx_busy());
      }
    }
  }
}

TEST(GfskTransceiver, AnyChunkingGivesIdenticalDecodes) {
  for (const auto r : {GfskReceiver::kDiscriminator, GfskReceiver::kEnergy}) {
    auto tx = make_gfsk_transceiver(settings(r));
    std::vector<cf32> air(333);
    for (std::uint32_t f = 0; f < 3; ++f) {
      const auto next = on_air(frame(*tx, FrameTag{1, 2, f}, make_payload(40, f)), 0, 517,
                               1.0F + static_cast<float>(f));
      air.insert(air.end(), next.begin(), next.end());
    }
    // Near the sensitivity: soft values are noisy, some decisions marginal.
    add_noise(air, std::pow(10.0, -0.6), 5);
    std::vector<Collector> runs(5);
    const std::size_t chunks[] = {1, 7, 250, 4096, air.size()};
    for (std::size_t i = 0; i < 5; ++i) {
      auto rx = make_gfsk_transceiver(settings(r));
      receive_chunked(*rx, air, chunks[i], runs[i]);
    }
    ASSERT_FALSE(runs[0].events.empty());
    for (std::size_t i = 1; i < 5; ++i) {
      ASSERT_EQ(runs[i].events.size(), runs[0].events.size()) << "chunk " << chunks[i];
      for (std::size_t e = 0; e < runs[0].events.size(); ++e) {
        EXPECT_EQ(runs[i].events[e].tag.serial, runs[0].events[e].tag.serial);
        EXPECT_EQ(runs[i].events[e].header_valid, runs[0].events[e].header_valid);
        EXPECT_EQ(runs[i].events[e].payload_valid, runs[0].events[e].payload_valid);
        EXPECT_EQ(runs[i].events[e].payload, runs[0].events[e].payload);
      }
    }
    EXPECT_EQ(runs[0].valid().size(), 3U);
  }
}

/// Conjugates (inverts the frequency of) symbols [first, last) of frame `f`.
void invert_symbols(std::vector<cf32>& f, unsigned k, std::size_t first, std::size_t last) {
  for (std::size_t n = first * k; n < last * k; ++n) f[n] = std::conj(f[n]);
}

TEST(GfskTransceiver, CorruptHeaderIsReportedInvalidAndTheNextFrameStillDecodes) {
  for (const auto r : {GfskReceiver::kDiscriminator, GfskReceiver::kEnergy}) {
    auto tx = make_gfsk_transceiver(settings(r));
    auto rx = make_gfsk_transceiver(settings(r));
    const auto p = make_payload(30, 1);
    auto bad = frame(*tx, FrameTag{1, 2, 3}, p);
    const std::size_t header = 8 * (8 + 4);  // first header symbol
    invert_symbols(bad, 8, header + 20, header + 30);
    auto air = on_air(bad, 200, 400, 0.3F);
    const auto good = on_air(frame(*tx, FrameTag{1, 2, 4}, p), 0, 400, 2.0F);
    air.insert(air.end(), good.begin(), good.end());
    add_noise(air, 0.01, 9);
    Collector c;
    receive_chunked(*rx, air, 250, c);
    ASSERT_EQ(c.events.size(), 2U);
    EXPECT_FALSE(c.events[0].header_valid);
    EXPECT_FALSE(c.events[0].payload_valid);
    EXPECT_TRUE(c.events[1].payload_valid);
    EXPECT_EQ(c.events[1].tag.serial, 4U);
  }
}

TEST(GfskTransceiver, CorruptPayloadIsReportedWithValidHeaderAndInvalidPayload) {
  for (const auto r : {GfskReceiver::kDiscriminator, GfskReceiver::kEnergy}) {
    auto tx = make_gfsk_transceiver(settings(r));
    auto rx = make_gfsk_transceiver(settings(r));
    const auto p = make_payload(60, 2);
    auto f = frame(*tx, FrameTag{6, 8, 77}, p);
    const std::size_t payload = 8 * (8 + 4 + 10);
    invert_symbols(f, 8, payload + 100, payload + 104);
    auto air = on_air(f, 150, 400, 4.0F);
    add_noise(air, 0.01, 10);
    Collector c;
    receive_chunked(*rx, air, 250, c);
    ASSERT_EQ(c.events.size(), 1U);
    EXPECT_TRUE(c.events[0].header_valid);
    EXPECT_FALSE(c.events[0].payload_valid);
    EXPECT_EQ(c.events[0].tag.serial, 77U);
    EXPECT_EQ(c.events[0].payload.size(), p.size());
  }
}

TEST(GfskTransceiver, FrameSamplesMatchesTransmitWhichZeroFillsAtUnitAmplitude) {
  for (const float bt : {0.0F, 0.5F, 0.2F}) {
    for (const unsigned k : {2U, 8U}) {
      GfskSettings s = settings(GfskReceiver::kDiscriminator, k, 1.0F, bt);
      s.preamble_bytes = 5;
      auto tx = make_gfsk_transceiver(s);
      for (const std::size_t n : {0U, 1U, 80U, 255U}) {
        EXPECT_FALSE(tx->tx_busy());
        const std::size_t len = tx->start_frame(FrameTag{}, make_payload(n, 3));
        ASSERT_EQ(len, tx->frame_samples(n));
        EXPECT_TRUE(tx->tx_busy());
        std::vector<cf32> a(len / 2, cf32{5.0F, 5.0F});
        EXPECT_EQ(tx->transmit(a), a.size());
        std::vector<cf32> b(len - a.size() + 100, cf32{5.0F, 5.0F});
        EXPECT_EQ(tx->transmit(b), len - a.size());
        EXPECT_FALSE(tx->tx_busy());
        for (std::size_t i = 0; i < b.size(); ++i) {
          if (i < len - a.size()) {
            EXPECT_NEAR(std::abs(b[i]), 1.0F, 1e-5F);
          } else {
            EXPECT_EQ(b[i], cf32{});
          }
        }
        std::vector<cf32> idle(10, cf32{1.0F, 1.0F});
        EXPECT_EQ(tx->transmit(idle), 0U);
        EXPECT_EQ(idle[9], cf32{});
      }
      // 8 symbols per payload octet; (N + L - 1) k in all.
      EXPECT_EQ(tx->frame_samples(81) - tx->frame_samples(80), 8U * k);
    }
  }
  EXPECT_EQ(make_gfsk_transceiver(GfskSettings{})->frame_samples(80), (832U + 2U) * 8U);
}

TEST(GfskTransceiver, DecodeComesWithinRxLatencyOfTheFrameEndAndResetAbandonsAFrame) {
  for (const auto r : {GfskReceiver::kDiscriminator, GfskReceiver::kEnergy}) {
    for (const float bt : {0.0F, 0.5F}) {
      auto tx = make_gfsk_transceiver(settings(r, 8, 2.0F, bt));
      auto rx = make_gfsk_transceiver(settings(r, 8, 2.0F, bt));
      const std::size_t lead = 411;
      const auto f = frame(*tx, FrameTag{1, 2, 3}, make_payload(20, 4));
      auto air = on_air(f, lead, 200, 1.5F);
      add_noise(air, 0.01, 12);
      Collector c;
      receive_chunked(*rx, air, 1, c);  // one sample at a time: `fed` is exact
      ASSERT_EQ(c.valid().size(), 1U);
      EXPECT_LE(c.valid()[0].fed, lead + f.size() + rx->rx_latency_samples());
      EXPECT_GE(c.valid()[0].fed, lead + f.size() - rx->rx_latency_samples() - 4 * 8);

      // Half the frame, a reset, the rest: nothing is reported.
      Collector d;
      rx->receive(std::span(air).first(lead + f.size() / 2), d);
      EXPECT_TRUE(rx->rx_busy());
      rx->reset_receiver();
      EXPECT_FALSE(rx->rx_busy());
      rx->receive(std::span(air).subspan(lead + f.size() / 2), d);
      EXPECT_TRUE(d.events.empty());
    }
  }
}

TEST(GfskTransceiver, RandomTimingPhaseAndSmallCarrierOffsetDecode) {
  std::mt19937 rng(21);
  for (const auto r : {GfskReceiver::kDiscriminator, GfskReceiver::kEnergy}) {
    auto tx = make_gfsk_transceiver(settings(r));
    auto rx = make_gfsk_transceiver(settings(r));
    std::size_t ok = 0;
    for (std::uint32_t i = 0; i < 12; ++i) {
      // Up to +-1% of the symbol rate: 0.00125 cycles per sample at k = 8.
      const double cfo = (static_cast<double>(rng() % 2001) - 1000.0) * 1.25e-6;
      const auto p = make_payload(50, i);
      auto air = on_air(frame(*tx, FrameTag{2, 1, i}, p), rng() % 97, 300,
                        6.28F * static_cast<float>(rng() % 1000) / 1000.0F, cfo);
      add_noise(air, std::pow(10.0, -0.8), 100 + i);  // 8 dB per-sample SNR
      Collector c;
      receive_chunked(*rx, air, 250, c);
      for (const Event& e : c.valid()) ok += e.tag.serial == i && e.payload == p ? 1U : 0U;
    }
    EXPECT_EQ(ok, 12U) << static_cast<int>(r);
  }
}

TEST(GfskTransceiver, EventCarriesRssiEvmAndOneSoftValuePerSymbol) {
  auto tx = make_gfsk_transceiver(GfskSettings{});
  auto rx = make_gfsk_transceiver(GfskSettings{});
  struct Check final : RxHandler {
    void on_rx(const RxEvent& ev) override {
      ++count;
      rssi = ev.rssi_db;
      evm = ev.evm_db;
      symbols = ev.symbols.size();
      double mean = 0.0;
      for (const cf32& s : ev.symbols) mean += std::abs(s.real());
      mean_abs = mean / static_cast<double>(symbols);
    }
    int count = 0;
    float rssi = 0.0F;
    float evm = 0.0F;
    std::size_t symbols = 0;
    double mean_abs = 0.0;
  } check;
  auto air = on_air(frame(*tx, FrameTag{1, 2, 3}, make_payload(80, 5)), 100, 200, 0.0F, 0.0);
  for (auto& v : air) v *= 2.0F;  // 6 dB over unit power
  add_noise(air, 0.04, 13);       // 20 dB SNR
  rx->receive(air, check);
  ASSERT_EQ(check.count, 1);
  EXPECT_NEAR(check.rssi, 10.0 * std::log10(4.04), 0.2);
  EXPECT_EQ(check.symbols, 8U * (10 + 80 + 2));
  EXPECT_NEAR(check.mean_abs, 1.0, 1e-4);
  EXPECT_LT(check.evm, -10.0F);
}

TEST(GfskTransceiver, PayloadLongerThanTheReceiverAcceptsIsReportedInvalid) {
  GfskSettings small;
  small.max_payload_bytes = 50;
  auto tx = make_gfsk_transceiver(GfskSettings{});
  auto rx = make_gfsk_transceiver(small);
  auto air = on_air(frame(*tx, FrameTag{1, 2, 3}, make_payload(51, 1)), 100, 300, 0.0F);
  Collector c;
  rx->receive(air, c);
  ASSERT_EQ(c.events.size(), 1U);
  EXPECT_TRUE(c.events[0].header_valid);
  EXPECT_FALSE(c.events[0].payload_valid);
  auto small_tx = make_gfsk_transceiver(small);
  EXPECT_THROW(small_tx->start_frame(FrameTag{}, make_payload(51, 1)), std::invalid_argument);
}

}  // namespace
}  // namespace rfsitl::phy
