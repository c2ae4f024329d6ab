// The FakeTransceiver test double keeps the Transceiver contract, and decides a
// decode from the samples it is given: the engine tests that use it rely on
// exactly what is proved here.
#include "fake_transceiver.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

namespace rfsitl::testing {
namespace {

FakeConfig test_config() {
  FakeConfig c;
  c.header_samples = 100;
  c.samples_per_byte = 8;
  c.max_payload = 64;
  c.sensitivity_snr_db = 10.0;
  c.rx_latency_samples = 25;
  c.block_samples = 32;
  return c;
}

std::vector<std::uint8_t> bytes(std::size_t n, std::uint8_t first) {
  std::vector<std::uint8_t> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<std::uint8_t>(first + i);
  return v;
}

/// `total` samples of `tx`'s transmitter with one frame starting at sample `at`.
std::vector<cf32> send(FakeTransceiver& tx, std::size_t at, const phy::FrameTag& tag,
                       const std::vector<std::uint8_t>& payload, std::size_t total) {
  std::vector<cf32> x(total);
  tx.transmit(std::span(x).first(at));  // idle: zeros, the clock runs
  tx.start_frame(tag, payload);
  tx.transmit(std::span(x).subspan(at));
  return x;
}

/// What a receiver hears: sum of gain * signal, plus unit-power complex noise.
std::vector<cf32> hear(const std::vector<std::pair<double, const std::vector<cf32>*>>& parts,
                       std::size_t total, unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> n(0.0F, std::sqrt(0.5F));
  std::vector<cf32> y(total);
  for (cf32& v : y) v = {n(rng), n(rng)};
  for (const auto& [gain, x] : parts) {
    for (std::size_t t = 0; t < total; ++t) y[t] += static_cast<float>(gain) * (*x)[t];
  }
  return y;
}

double amplitude_for_snr_db(double snr_db) {
  return std::pow(10.0, snr_db / 20.0);
}

struct Got {
  NodeId src;
  NodeId dst;
  std::uint32_t serial;
  std::vector<std::uint8_t> payload;
  bool header_valid;
  bool payload_valid;
  std::size_t call_end;  // samples consumed once the call that reported it returns
  friend bool operator==(const Got&, const Got&) = default;
};

struct Handler final : phy::RxHandler {
  void on_rx(const phy::RxEvent& e) override {
    got.push_back({e.tag.src,
                   e.tag.dst,
                   e.tag.serial,
                   {e.payload.begin(), e.payload.end()},
                   e.header_valid,
                   e.payload_valid,
                   call_end});
  }
  std::vector<Got> got;
  std::size_t call_end = 0;
};

/// Feeds `y` to `rx` in chunks of `chunk` samples; returns what it reported.
std::vector<Got> feed(FakeTransceiver& rx, const std::vector<cf32>& y, std::size_t chunk) {
  Handler h;
  for (std::size_t at = 0; at < y.size(); at += chunk) {
    const std::size_t n = std::min(chunk, y.size() - at);
    h.call_end = at + n;
    rx.receive(std::span(y).subspan(at, n), h);
  }
  return h.got;
}

struct Medium {
  std::shared_ptr<FakeAir> air = std::make_shared<FakeAir>();
  FakeTransceiver a{test_config(), air};
  FakeTransceiver b{test_config(), air};
  FakeTransceiver c{test_config(), air};
};

const phy::FrameTag kTagA{1, 2, 11};
const phy::FrameTag kTagC{3, 2, 33};

TEST(FakeTransceiver, FrameIsHeaderPlusSamplesPerByteOfUnitPowerThenZeros) {
  Medium m;
  EXPECT_EQ(m.a.frame_samples(0), 100U);
  EXPECT_EQ(m.a.frame_samples(10), 180U);
  EXPECT_FALSE(m.a.tx_busy());
  EXPECT_EQ(m.a.start_frame(kTagA, bytes(10, 0)), 180U);
  EXPECT_TRUE(m.a.tx_busy());
  std::vector<cf32> out(70);
  EXPECT_EQ(m.a.transmit(out), 70U);
  EXPECT_EQ(m.a.transmit(out), 70U);
  EXPECT_EQ(m.a.transmit(out), 40U);  // signal counted from the start of out
  for (std::size_t t = 0; t < out.size(); ++t) {
    EXPECT_NEAR(std::abs(out[t]), t < 40 ? 1.0F : 0.0F, 1e-6F) << t;
  }
  EXPECT_FALSE(m.a.tx_busy());
  EXPECT_EQ(m.a.calls().start_frame, 1U);
  EXPECT_EQ(m.a.calls().transmit, 3U);
  EXPECT_EQ(m.a.calls().contract_violations, 0U);
}

TEST(FakeTransceiver, DecodeIsReportedExactlyLatencyAfterTheLastSampleWhateverTheChunking) {
  Medium m;
  const auto x = send(m.a, 150, kTagA, bytes(20, 7), 700);  // frame [150, 410)
  const auto y = hear({{amplitude_for_snr_db(30.0), &x}}, 700);
  const std::vector<Got> one_by_one = feed(m.b, y, 1);
  ASSERT_EQ(one_by_one.size(), 1U);
  const Got& g = one_by_one.front();
  EXPECT_EQ(g.serial, kTagA.serial);
  EXPECT_EQ(g.src, kTagA.src);
  EXPECT_EQ(g.payload, bytes(20, 7));
  EXPECT_TRUE(g.header_valid);
  EXPECT_TRUE(g.payload_valid);
  EXPECT_EQ(g.call_end, 150U + 260U + 25U);  // the call that consumed the due sample
  ASSERT_EQ(m.b.decodes().size(), 1U);
  EXPECT_EQ(m.b.decodes().front().frame_start, 150);
  EXPECT_EQ(m.b.decodes().front().reported_at, 435);
  EXPECT_NEAR(m.b.decodes().front().min_sinr_db, 30.0, 3.0);
  for (const std::size_t chunk : {7U, 64U, 435U, 700U}) {
    Medium fresh;
    send(fresh.a, 150, kTagA, bytes(20, 7), 700);  // the same frame on a fresh air
    std::vector<Got> got = feed(fresh.b, y, chunk);
    ASSERT_EQ(got.size(), 1U) << chunk;
    EXPECT_GE(got.front().call_end, 435U) << chunk;
    EXPECT_LT(got.front().call_end - chunk, 435U) << chunk;
    got.front().call_end = g.call_end;
    EXPECT_EQ(got, one_by_one) << chunk;
    EXPECT_EQ(fresh.b.decodes().front().reported_at, 435) << chunk;
  }
}

TEST(FakeTransceiver, DecodesOnlyAtOrAboveItsSensitivity) {
  for (const double snr : {4.0, 16.0}) {
    Medium m;
    const auto x = send(m.a, 0, kTagA, bytes(30, 0), 500);
    feed(m.b, hear({{amplitude_for_snr_db(snr), &x}}, 500), 100);
    EXPECT_EQ(m.b.decodes().size(), snr > 10.0 ? 1U : 0U) << snr << " dB";
  }
}

TEST(FakeTransceiver, EqualPowerOverlapLosesBothAndAFarStrongerFrameIsCaptured) {
  for (const double weaker_by_db : {0.0, 40.0}) {
    Medium m;
    const auto xa = send(m.a, 0, kTagA, bytes(30, 0), 600);
    const auto xc = send(m.c, 50, kTagC, bytes(30, 0), 600);
    const double strong = amplitude_for_snr_db(50.0);
    const double weak = amplitude_for_snr_db(50.0 - weaker_by_db);
    feed(m.b, hear({{strong, &xa}, {weak, &xc}}, 600), 128);
    if (weaker_by_db == 0.0) {
      EXPECT_TRUE(m.b.decodes().empty());
    } else {
      ASSERT_EQ(m.b.decodes().size(), 1U);
      EXPECT_EQ(m.b.decodes().front().tag.serial, kTagA.serial);
      EXPECT_TRUE(m.b.decodes().front().payload_valid);
    }
  }
}

TEST(FakeTransceiver, OverlapInThePayloadOnlyIsACrcFailure) {
  Medium m;
  const auto xa = send(m.a, 0, kTagA, bytes(50, 0), 900);    // [0, 500), payload from 100
  const auto xc = send(m.c, 300, kTagC, bytes(20, 0), 900);  // [300, 560): header hit by a
  const double amp = amplitude_for_snr_db(40.0);
  const std::vector<Got> got = feed(m.b, hear({{amp, &xa}, {amp, &xc}}, 900), 250);
  ASSERT_EQ(got.size(), 1U);
  EXPECT_EQ(got.front().serial, kTagA.serial);
  EXPECT_TRUE(got.front().header_valid);
  EXPECT_FALSE(got.front().payload_valid);
}

TEST(FakeTransceiver, MissedSamplesLoseTheFrameInTheHeaderOrItsPayloadAfterIt) {
  // begin_tick jumps the receiver's clock: the samples in between never
  // reached it (a tick it was not run in). The frame's header is [0, 100).
  struct Gap {
    std::size_t from, to;
  };
  for (const Gap gap : {Gap{40, 80}, Gap{150, 300}}) {
    Medium m;
    const auto x = send(m.a, 0, kTagA, bytes(50, 0), 800);
    const auto y = hear({{amplitude_for_snr_db(40.0), &x}}, 800);
    Handler h;
    m.b.receive(std::span(y).first(gap.from), h);
    m.b.begin_tick(1, static_cast<SampleTime>(gap.to));
    m.b.receive(std::span(y).subspan(gap.to), h);
    if (gap.from < 100) {
      EXPECT_TRUE(h.got.empty());
    } else {
      ASSERT_EQ(h.got.size(), 1U);
      EXPECT_TRUE(h.got.front().header_valid);
      EXPECT_FALSE(h.got.front().payload_valid);
    }
  }
}

TEST(FakeTransceiver, RxBusyFromTheFirstGoodBlockUntilTheDecodeAndResetAbandonsTheFrame) {
  for (const bool reset : {false, true}) {
    Medium m;
    const auto x = send(m.a, 100, kTagA, bytes(10, 0), 600);  // [100, 280), due at 305
    const auto y = hear({{amplitude_for_snr_db(30.0), &x}}, 600);
    Handler h;
    auto feed_to = [&, at = std::size_t{0}](std::size_t end) mutable {
      m.b.receive(std::span(y).subspan(at, end - at), h);
      at = end;
    };
    feed_to(120);
    EXPECT_FALSE(m.b.rx_busy()) << "a frame start not yet judged";
    feed_to(132);
    EXPECT_TRUE(m.b.rx_busy());
    if (reset) {
      m.b.reset_receiver();
      EXPECT_FALSE(m.b.rx_busy());
    }
    feed_to(304);
    EXPECT_EQ(m.b.rx_busy(), !reset) << "waiting out the latency";
    feed_to(305);
    EXPECT_FALSE(m.b.rx_busy());
    EXPECT_EQ(h.got.size(), reset ? 0U : 1U);
    EXPECT_EQ(m.b.calls().reset_receiver, reset ? 1U : 0U);
    EXPECT_EQ(m.b.calls().samples_received, 305U);
  }
}

TEST(FakeTransceiver, NoiseAloneIsNeverAFrame) {
  Medium m;
  const auto x = send(m.a, 0, kTagA, bytes(40, 0), 800);
  feed(m.b, hear({{0.0, &x}}, 800, 3), 100);  // the frame is registered, but has no link
  EXPECT_TRUE(m.b.decodes().empty());
  EXPECT_FALSE(m.b.rx_busy());
}

TEST(FakeTransceiver, CountsContractBreaches) {
  Medium m;
  m.a.begin_tick(0, 0);
  m.a.start_frame(kTagA, bytes(10, 0));
  m.a.start_frame(kTagA, bytes(10, 0));  // while busy
  EXPECT_EQ(m.a.calls().contract_violations, 1U);
  m.a.begin_tick(1, 1000);  // busy, but no transmit() in tick 0
  EXPECT_EQ(m.a.calls().contract_violations, 2U);
  m.b.begin_tick(5, 5000);
  m.b.begin_tick(4, 4000);               // backwards
  m.b.start_frame(kTagA, bytes(65, 0));  // beyond max_payload
  EXPECT_EQ(m.b.calls().contract_violations, 2U);
  EXPECT_EQ(m.b.calls().begin_tick, 2U);
}

}  // namespace
}  // namespace rfsitl::testing
