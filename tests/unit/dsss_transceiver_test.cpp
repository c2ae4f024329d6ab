#include "phy/dsss/dsss_transceiver.hpp"

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

struct Decode {
  FrameTag tag;
  std::vector<std::uint8_t> payload;
  bool header_valid = false;
  bool payload_valid = false;
  std::size_t fed = 0;  // samples fed when it was reported
};

class Collector final : public RxHandler {
 public:
  void on_rx(const RxEvent& ev) override {
    decodes.push_back(
        {ev.tag, {ev.payload.begin(), ev.payload.end()}, ev.header_valid, ev.payload_valid, fed});
  }
  std::size_t valid() const {
    return static_cast<std::size_t>(std::count_if(decodes.begin(), decodes.end(),
                                                  [](const Decode& d) { return d.payload_valid; }));
  }
  std::vector<Decode> decodes;
  std::size_t fed = 0;
};

std::vector<std::uint8_t> random_payload(std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<std::uint8_t> p(n);
  for (auto& b : p) b = static_cast<std::uint8_t>(rng());
  return p;
}

/// The frame's samples, produced by transmit() in 250-sample ticks.
std::vector<cf32> transmit_frame(Transceiver& tx, const FrameTag& tag,
                                 const std::vector<std::uint8_t>& payload) {
  const std::size_t len = tx.start_frame(tag, payload);
  std::vector<cf32> out;
  std::vector<cf32> tick(250);
  while (tx.tx_busy()) {
    const std::size_t n = tx.transmit(tick);
    out.insert(out.end(), tick.begin(), tick.begin() + static_cast<std::ptrdiff_t>(n));
  }
  EXPECT_EQ(out.size(), len);
  return out;
}

/// Frames separated by `gap` samples, through a channel of random constant
/// phase, plus complex AWGN at `snr_db` per sample relative to the unit-power signal.
std::vector<cf32> over_the_air(const std::vector<std::vector<cf32>>& frames, double snr_db,
                               std::uint32_t seed, std::size_t gap = 700) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> phase(0.0F, 6.2831853F);
  std::vector<cf32> x(gap);
  for (const auto& f : frames) {
    const cf32 c = std::polar(1.0F, phase(rng));
    for (const cf32& s : f) x.push_back(c * s);
    x.resize(x.size() + gap);
  }
  std::normal_distribution<float> g(
      0.0F, static_cast<float>(std::sqrt(0.5 * std::pow(10.0, -snr_db / 10.0))));
  for (cf32& s : x) s += cf32{g(rng), g(rng)};
  return x;
}

void feed(Transceiver& rx, std::span<const cf32> x, Collector& c, std::size_t tick = 250) {
  for (std::size_t i = 0; i < x.size(); i += tick) {
    const auto chunk = x.subspan(i, std::min(tick, x.size() - i));
    c.fed = i + chunk.size();
    rx.receive(chunk, c);
  }
}

DsssSettings settings(const std::string& code, const std::string& modulation = "dbpsk",
                      unsigned sps = 1) {
  DsssSettings s;
  s.code = code;
  s.modulation = modulation;
  s.samples_per_chip = sps;
  return s;
}

/// Payload-valid decodes of `count` 80-byte frames sent at `snr_db`.
std::size_t decoded_frames(const DsssSettings& s, std::size_t count, double snr_db,
                           std::uint32_t seed) {
  auto tx = make_dsss_transceiver(s);
  auto rx = make_dsss_transceiver(s);
  std::vector<std::vector<cf32>> frames;
  for (std::size_t k = 0; k < count; ++k) {
    frames.push_back(transmit_frame(*tx, {1, 2, static_cast<std::uint32_t>(k)},
                                    random_payload(80, seed + static_cast<std::uint32_t>(k))));
  }
  Collector c;
  feed(*rx, over_the_air(frames, snr_db, seed), c);
  return c.valid();
}

void expect_throws_naming(const DsssSettings& s, const std::string& field) {
  try {
    make_dsss_transceiver(s);
    ADD_FAILURE() << "accepted a bad " << field;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

TEST(DsssTransceiver, InvalidSettingsThrowNamingTheField) {
  expect_throws_naming(settings("gold255"), "code");
  expect_throws_naming(settings("barker13"), "code");
  expect_throws_naming(settings("mseq31", "qpsk"), "modulation");
  expect_throws_naming(settings("mseq31", "dbpsk", 0), "samples_per_chip");
  expect_throws_naming(settings("mseq31", "dbpsk", 9), "samples_per_chip");
  DsssSettings s = settings("mseq31");
  s.max_payload_bytes = 0;
  expect_throws_naming(s, "max_payload_bytes");
  s.max_payload_bytes = 70000;
  expect_throws_naming(s, "max_payload_bytes");
}

TEST(DsssTransceiver, TransmitHonoursTheTxContract) {
  for (const auto& s : {settings("barker11"), settings("mseq31", "dqpsk", 3)}) {
    auto tx = make_dsss_transceiver(s);
    const auto payload = random_payload(37, 1);
    const std::size_t len = tx->start_frame({4, 5, 6}, payload);
    EXPECT_EQ(len, tx->frame_samples(payload.size()));
    std::size_t signal = 0;
    double power = 0.0;
    std::vector<cf32> tick(250);
    while (tx->tx_busy()) {
      std::fill(tick.begin(), tick.end(), cf32{7.0F, -7.0F});  // must be overwritten
      const std::size_t n = tx->transmit(tick);
      for (std::size_t i = 0; i < n; ++i) power += std::norm(tick[i]);
      for (std::size_t i = n; i < tick.size(); ++i) ASSERT_EQ(tick[i], cf32{}) << "zero fill";
      signal += n;
      ASSERT_LE(signal, len);
    }
    EXPECT_EQ(signal, len);
    EXPECT_NEAR(power / static_cast<double>(len), 1.0, 1e-6) << "unit mean power";
    EXPECT_EQ(tx->transmit(tick), 0U);
  }
}

TEST(DsssTransceiver, FramesDecodeExactlyAt10dBForEveryModulationCodeAndChipRate) {
  std::uint32_t seed = 100;
  for (const char* modulation : {"dbpsk", "dqpsk"}) {
    for (const char* code : {"barker11", "mseq31", "gold63:5", "mseq127"}) {
      for (const unsigned sps : {1U, 2U}) {
        const DsssSettings s = settings(code, modulation, sps);
        auto tx = make_dsss_transceiver(s);
        auto rx = make_dsss_transceiver(s);
        const std::vector<FrameTag> tags = {{1, 2, 1000 + seed}, {3, kBroadcastId, 7}};
        const std::vector<std::vector<std::uint8_t>> payloads = {random_payload(40, seed),
                                                                 random_payload(1, seed + 1)};
        const std::vector<std::vector<cf32>> frames = {transmit_frame(*tx, tags[0], payloads[0]),
                                                       transmit_frame(*tx, tags[1], payloads[1])};
        Collector c;
        feed(*rx, over_the_air(frames, 10.0, seed++), c);
        ASSERT_EQ(c.decodes.size(), 2U) << code << " " << modulation << " sps " << sps;
        for (std::size_t k = 0; k < 2; ++k) {
          const Decode& d = c.decodes[k];
          EXPECT_TRUE(d.header_valid && d.payload_valid) << code << " " << modulation;
          EXPECT_EQ(d.tag.src, tags[k].src);
          EXPECT_EQ(d.tag.dst, tags[k].dst);
          EXPECT_EQ(d.tag.serial, tags[k].serial);
          EXPECT_EQ(d.payload, payloads[k]);
        }
        EXPECT_FALSE(rx->rx_busy());
      }
    }
  }
}

TEST(DsssTransceiver, Mseq127DecodesAtMinus5dB) {
  // 21 dB of processing gain puts -5 dB per sample at +16 dB after despreading.
  EXPECT_EQ(decoded_frames(settings("mseq127"), 5, -5.0, 7), 5U);
}

TEST(DsssTransceiver, LongerCodeShowsItsProcessingGainInThePer) {
  // At -6 dB per sample Barker-11 (10.4 dB gain) leaves DBPSK ~4 dB of Eb/N0:
  // nearly every 80-byte frame fails. mseq127 (21 dB) leaves ~15 dB: none fails.
  const std::size_t frames = 10;
  const std::size_t barker = decoded_frames(settings("barker11"), frames, -6.0, 21);
  const std::size_t mseq = decoded_frames(settings("mseq127"), frames, -6.0, 21);
  EXPECT_LE(barker, 2U) << "Barker-11 PER " << 1.0 - static_cast<double>(barker) / frames;
  EXPECT_GE(mseq, 9U) << "mseq127 PER " << 1.0 - static_cast<double>(mseq) / frames;
}

TEST(DsssTransceiver, NoiseAloneDecodesNothing) {
  for (const char* code : {"barker11", "mseq127"}) {
    auto rx = make_dsss_transceiver(settings(code));
    Collector c;
    feed(*rx, over_the_air({}, 0.0, 99, 1'000'000), c);
    EXPECT_EQ(c.valid(), 0U) << code;
    for (const Decode& d : c.decodes) EXPECT_FALSE(d.header_valid) << code;
  }
}

TEST(DsssTransceiver, SilenceOfExactZerosDecodesNothingAndStaysIdle) {
  auto rx = make_dsss_transceiver(settings("mseq31"));
  Collector c;
  const std::vector<cf32> zeros(20'000);
  feed(*rx, zeros, c);
  EXPECT_TRUE(c.decodes.empty());
  EXPECT_FALSE(rx->rx_busy());
}

TEST(DsssTransceiver, ReportsTheDecodeWithinRxLatencyOfTheFramesEnd) {
  for (const unsigned sps : {1U, 3U}) {
    const DsssSettings s = settings("mseq31", "dbpsk", sps);
    auto tx = make_dsss_transceiver(s);
    auto rx = make_dsss_transceiver(s);
    const auto frame = transmit_frame(*tx, {1, 2, 3}, random_payload(20, 4));
    std::vector<cf32> x(500);
    x.insert(x.end(), frame.begin(), frame.end());
    const std::size_t end = x.size();
    x.resize(end + 1000);
    Collector c;
    // Exactly up to the frame's end plus the declared latency...
    feed(*rx, std::span(x).first(end + rx->rx_latency_samples()), c, 100);
    EXPECT_EQ(c.valid(), 1U) << "sps " << sps;
    EXPECT_FALSE(rx->rx_busy());
  }
}

TEST(DsssTransceiver, RxBusyFromAcquisitionUntilTheDecode) {
  const DsssSettings s = settings("mseq31");
  auto tx = make_dsss_transceiver(s);
  auto rx = make_dsss_transceiver(s);
  const auto frame = transmit_frame(*tx, {1, 2, 3}, random_payload(10, 4));
  const auto x = over_the_air({frame}, 20.0, 5, 2000);
  Collector c;
  feed(*rx, std::span(x).first(2000), c);
  EXPECT_FALSE(rx->rx_busy()) << "noise only so far";
  feed(*rx, std::span(x).subspan(2000, frame.size() / 2), c);
  EXPECT_TRUE(rx->rx_busy()) << "half way through the frame";
  EXPECT_TRUE(c.decodes.empty());
  feed(*rx, std::span(x).subspan(2000 + frame.size() / 2), c);
  EXPECT_EQ(c.valid(), 1U);
  EXPECT_FALSE(rx->rx_busy());
}

TEST(DsssTransceiver, ResetReceiverAbandonsTheFrameInProgress) {
  const DsssSettings s = settings("barker11");
  auto tx = make_dsss_transceiver(s);
  auto rx = make_dsss_transceiver(s);
  const auto frame = transmit_frame(*tx, {1, 2, 3}, random_payload(10, 4));
  const auto x = over_the_air({frame, frame}, 20.0, 6, 500);
  Collector c;
  feed(*rx, std::span(x).first(500 + frame.size() / 2), c);
  ASSERT_TRUE(rx->rx_busy());
  rx->reset_receiver();
  EXPECT_FALSE(rx->rx_busy());
  feed(*rx, std::span(x).subspan(500 + frame.size() / 2), c);
  ASSERT_EQ(c.valid(), 1U) << "only the second copy";
}

TEST(DsssTransceiver, CorruptedPayloadIsReportedAsCrcFailureWithItsTag) {
  const DsssSettings s = settings("mseq31");
  auto tx = make_dsss_transceiver(s);
  auto rx = make_dsss_transceiver(s);
  auto frame = transmit_frame(*tx, {9, 8, 77}, random_payload(30, 4));
  // Flip the sign of one payload symbol (after sync and header), no noise.
  const std::size_t symbol = 32 + 16 + 104 + 50;
  for (std::size_t i = symbol * 31; i < (symbol + 1) * 31; ++i) frame[i] = -frame[i];
  std::vector<cf32> x(300);
  x.insert(x.end(), frame.begin(), frame.end());
  x.resize(x.size() + 300);
  Collector c;
  feed(*rx, x, c);
  ASSERT_EQ(c.decodes.size(), 1U);
  EXPECT_TRUE(c.decodes[0].header_valid);
  EXPECT_FALSE(c.decodes[0].payload_valid);
  EXPECT_EQ(c.decodes[0].tag.serial, 77U);
}

TEST(DsssTransceiver, SensitivityFollowsProcessingGainAndModulation) {
  const double barker = make_dsss_transceiver(settings("barker11"))->sensitivity_snr_db();
  const double mseq = make_dsss_transceiver(settings("mseq127"))->sensitivity_snr_db();
  const double mseq2 = make_dsss_transceiver(settings("mseq127", "dbpsk", 2))->sensitivity_snr_db();
  const double dqpsk = make_dsss_transceiver(settings("mseq127", "dqpsk"))->sensitivity_snr_db();
  EXPECT_NEAR(barker - mseq, 10.0 * std::log10(127.0 / 11.0), 0.01);
  EXPECT_NEAR(mseq - mseq2, 3.01, 0.01);
  EXPECT_GT(dqpsk, mseq);
  EXPECT_LT(mseq, 0.0);
}

}  // namespace
}  // namespace rfsitl::phy
