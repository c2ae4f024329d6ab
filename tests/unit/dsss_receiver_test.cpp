// Receiver behaviour beyond the basic decode: chip timing tracking, carrier
// offset, back-to-back frames, frames from the first sample, the listening set.
#include "phy/dsss/receiver.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>
#include <span>
#include <stdexcept>
#include <vector>

#include "phy/dsss/codes.hpp"
#include "phy/dsss/differential_psk.hpp"
#include "phy/dsss/spreader.hpp"

namespace rfsitl::phy::dsss {
namespace {

struct Sink final : FrameSink {
  void on_frame(const ReceivedFrame& f) override {
    if (f.payload_valid) {
      serials.push_back(f.header.serial);
      codes.push_back(f.code_id);
      snr_db.push_back(f.despread_snr_db);
    }
    ++events;
  }
  std::vector<std::uint32_t> serials;
  std::vector<std::size_t> codes;
  std::vector<float> snr_db;
  std::size_t events = 0;
};

std::vector<cf32> frame(const std::vector<Chip>& code, unsigned sps, std::uint32_t serial,
                        Modulation m = Modulation::kDbpsk, std::size_t bytes = 20) {
  std::vector<std::uint8_t> payload(bytes);
  for (std::size_t i = 0; i < bytes; ++i) payload[i] = static_cast<std::uint8_t>(serial * 7 + i);
  const FrameHeader h{m, static_cast<std::uint16_t>(bytes), 1, 2, serial, 0};
  return spread(frame_symbols(h, payload), code, sps);
}

void add_noise(std::vector<cf32>& x, double snr_db, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> g(
      0.0F, static_cast<float>(std::sqrt(0.5 * std::pow(10.0, -snr_db / 10.0))));
  for (cf32& s : x) s += cf32{g(rng), g(rng)};
}

void push_in_ticks(DsssReceiver& rx, std::span<const cf32> x, FrameSink& sink) {
  for (std::size_t i = 0; i < x.size(); i += 250)
    rx.push(x.subspan(i, std::min<std::size_t>(250, x.size() - i)), sink);
}

TEST(DsssReceiver, TracksChipTimingSlipsOfSeveralChipsAcrossAFrame) {
  // S = 4: every 24 code periods from the header on, the sender's clock gains
  // (or loses) one sample; over the frame that is 3 chips, so a receiver that
  // kept its acquisition timing would despread noise by the end.
  const unsigned sps = 4;
  const auto code = code_by_name("mseq31").chips;
  const std::size_t period = code.size() * sps;
  for (const int direction : {+1, -1}) {
    const auto clean = frame(code, sps, 5, Modulation::kDbpsk, 40);
    std::vector<cf32> x(1000);
    std::size_t slips = 0;
    for (std::size_t i = 0; i < clean.size(); ++i) {
      const bool slip = i > 60 * period && i % (24 * period) == 0;
      if (slip && direction < 0) {
        ++slips;
        continue;  // drop a sample
      }
      x.push_back(clean[i]);
      if (slip) {
        ++slips;
        x.push_back(clean[i]);  // repeat a sample
      }
    }
    x.resize(x.size() + 1000);
    ASSERT_GE(slips, 3 * sps) << "the test must slip by several chips";
    add_noise(x, 5.0, 9);
    DsssReceiver rx({sps, 256}, {{0, code}});
    Sink sink;
    push_in_ticks(rx, x, sink);
    ASSERT_EQ(sink.serials.size(), 1U) << "direction " << direction;
    EXPECT_EQ(sink.serials[0], 5U);
  }
}

TEST(DsssReceiver, ToleratesACarrierOffsetOfTwentyDegreesPerSymbol) {
  const auto code = code_by_name("mseq31").chips;
  auto x = frame(code, 1, 8, Modulation::kDbpsk, 60);
  x.insert(x.begin(), 500, cf32{});
  x.resize(x.size() + 500);
  const double step = (20.0 / 360.0) * 2.0 * M_PI / static_cast<double>(code.size());
  for (std::size_t n = 0; n < x.size(); ++n) {
    x[n] *= std::polar(1.0F, static_cast<float>(step * static_cast<double>(n)));
  }
  add_noise(x, 5.0, 3);
  DsssReceiver rx({1, 256}, {{0, code}});
  Sink sink;
  push_in_ticks(rx, x, sink);
  ASSERT_EQ(sink.serials.size(), 1U);
}

TEST(DsssReceiver, DecodesBackToBackFramesWithoutGaps) {
  const auto code = code_by_name("barker11").chips;
  std::vector<cf32> x;
  for (std::uint32_t k = 0; k < 4; ++k) {
    const auto f = frame(code, 2, k, k % 2 == 0 ? Modulation::kDbpsk : Modulation::kDqpsk);
    x.insert(x.end(), f.begin(), f.end());
  }
  x.resize(x.size() + 100);
  add_noise(x, 12.0, 4);
  DsssReceiver rx({2, 256}, {{0, code}});
  Sink sink;
  push_in_ticks(rx, x, sink);
  EXPECT_EQ(sink.serials, (std::vector<std::uint32_t>{0, 1, 2, 3}));
}

TEST(DsssReceiver, DecodesAFrameThatStartsAtItsFirstSample) {
  // What the engine does after a node's own transmission: reset, then a peer's
  // frame may already be on the air.
  const auto code = code_by_name("gold63:2").chips;
  auto x = frame(code, 1, 3);
  x.resize(x.size() + 100);
  add_noise(x, 3.0, 5);
  DsssReceiver rx({1, 256}, {{0, code}});
  Sink sink;
  push_in_ticks(rx, std::span(x).first(1000), sink);  // some history to forget
  rx.reset();
  push_in_ticks(rx, x, sink);
  ASSERT_EQ(sink.serials.size(), 1U);
}

TEST(DsssReceiver, DespreadSnrEstimateFollowsTheProcessingGain) {
  // At 0 dB per sample, mseq127 despreads to ~21 dB: the estimate must be
  // within a few dB (it is a moment estimate, biased at low SNR only).
  const auto code = code_by_name("mseq127").chips;
  auto x = frame(code, 1, 1, Modulation::kDbpsk, 40);
  x.insert(x.begin(), 300, cf32{});
  x.resize(x.size() + 300);
  add_noise(x, 0.0, 6);
  DsssReceiver rx({1, 256}, {{0, code}});
  Sink sink;
  push_in_ticks(rx, x, sink);
  ASSERT_EQ(sink.snr_db.size(), 1U);
  EXPECT_NEAR(sink.snr_db[0], 10.0 * std::log10(127.0), 3.0);
}

TEST(DsssReceiver, RejectsListeningSetsItCannotRun) {
  const auto a = code_by_name("mseq31").chips;
  const auto b = code_by_name("mseq63").chips;
  EXPECT_THROW(DsssReceiver({1, 256}, {}), std::invalid_argument);
  EXPECT_THROW(DsssReceiver({1, 256}, {{0, a}, {1, b}}), std::invalid_argument);
  EXPECT_THROW(DsssReceiver({0, 256}, {{0, a}}), std::invalid_argument);
  EXPECT_THROW(DsssReceiver({9, 256}, {{0, a}}), std::invalid_argument);
  DsssReceiver rx({1, 256}, {{0, a}});
  EXPECT_THROW(rx.set_codes({{1, b}}), std::invalid_argument);
  EXPECT_THROW(rx.set_codes({{0, a}, {1, a}, {2, a}, {3, a}, {4, a}}), std::invalid_argument);
}

}  // namespace
}  // namespace rfsitl::phy::dsss
