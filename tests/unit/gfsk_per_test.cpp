#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "fast_gmsk_test_support.hpp"
#include "phy/gfsk/gfsk_transceiver.hpp"

namespace rfsitl::phy {
namespace {

using fast_gmsk_test::add_noise;
using fast_gmsk_test::Collector;
using fast_gmsk_test::make_payload;
using fast_gmsk_test::put_frame;
using fast_gmsk_test::receive_chunked;

/// Share of `frames` 80-byte frames (random phase and offset, back to back
/// with gaps, in one stream) not decoded exactly, at a per-sample SNR.
double per(const GfskSettings& s, double snr_db, std::uint32_t frames, std::uint32_t seed) {
  auto tx = make_gfsk_transceiver(s);
  auto rx = make_gfsk_transceiver(s);
  std::mt19937 rng(seed);
  std::vector<cf32> air;
  std::vector<std::vector<std::uint8_t>> sent;
  std::size_t at = 0;
  for (std::uint32_t f = 0; f < frames; ++f) {
    sent.push_back(make_payload(80, seed + f));
    at += 200 + rng() % 200;
    at += put_frame(*tx, FrameTag{1, 2, f}, sent.back(), air, at,
                    static_cast<float>(rng() % 628) / 100.0F);
  }
  air.resize(at + 500);
  add_noise(air, std::pow(10.0, -snr_db / 10.0), seed);
  Collector c;
  receive_chunked(*rx, air, 250, c);
  std::uint32_t ok = 0;
  for (const auto& e : c.valid()) ok += e.tag.serial < frames && e.payload == sent[e.tag.serial];
  return 1.0 - static_cast<double>(ok) / frames;
}

TEST(GfskPer, LowThreeDecibelsAboveSensitivityAndHighFarBelowIt) {
  for (const auto r : {GfskReceiver::kDiscriminator, GfskReceiver::kEnergy}) {
    GfskSettings s;
    s.receiver = r;
    const double sens = make_gfsk_transceiver(s)->sensitivity_snr_db();
    EXPECT_LE(per(s, sens + 3.0, 30, 1), 0.04) << static_cast<int>(r);
    EXPECT_GE(per(s, sens - 6.0, 30, 2), 0.95) << static_cast<int>(r);
  }
}

TEST(GfskPer, NoiseAloneGivesNoDecodeAndLeavesTheReceiverIdle) {
  for (const auto r : {GfskReceiver::kDiscriminator, GfskReceiver::kEnergy}) {
    GfskSettings s;
    s.receiver = r;
    auto rx = make_gfsk_transceiver(s);
    std::vector<cf32> noise(200000);
    add_noise(noise, 1.0, 17);
    Collector c;
    receive_chunked(*rx, noise, 250, c);
    EXPECT_TRUE(c.events.empty());
    EXPECT_FALSE(rx->rx_busy());
  }
}

TEST(GfskPer, SensitivityScalesWithSamplesPerSymbolAtEqualEbN0) {
  GfskSettings s;
  const double k8 = make_gfsk_transceiver(s)->sensitivity_snr_db();
  s.samples_per_symbol = 4;
  EXPECT_NEAR(make_gfsk_transceiver(s)->sensitivity_snr_db(), k8 + 10.0 * std::log10(2.0), 1e-9);
}

void expect_rejected(const GfskSettings& s, const std::string& field) {
  try {
    make_gfsk_transceiver(s);
    ADD_FAILURE() << field << " accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

TEST(GfskSettingsValidation, OutOfRangeFieldsAreNamedAndEdgesAccepted) {
  const auto with = [](auto change) {
    GfskSettings s;
    change(s);
    return s;
  };
  expect_rejected(with([](GfskSettings& s) { s.samples_per_symbol = 1; }), "samples_per_symbol");
  expect_rejected(with([](GfskSettings& s) { s.samples_per_symbol = 33; }), "samples_per_symbol");
  expect_rejected(with([](GfskSettings& s) { s.modulation_index = 0.0F; }), "modulation_index");
  expect_rejected(with([](GfskSettings& s) { s.modulation_index = 2.01F; }), "modulation_index");
  expect_rejected(with([](GfskSettings& s) { s.modulation_index = NAN; }), "modulation_index");
  expect_rejected(with([](GfskSettings& s) {
                    s.samples_per_symbol = 2;
                    s.modulation_index = 1.5F;
                  }),
                  "modulation_index");
  expect_rejected(with([](GfskSettings& s) { s.bandwidth_time = 0.1F; }), "bandwidth_time");
  expect_rejected(with([](GfskSettings& s) { s.bandwidth_time = 1.5F; }), "bandwidth_time");
  expect_rejected(with([](GfskSettings& s) { s.bandwidth_time = -0.5F; }), "bandwidth_time");
  expect_rejected(with([](GfskSettings& s) { s.receiver = static_cast<GfskReceiver>(7); }),
                  "receiver");
  expect_rejected(with([](GfskSettings& s) { s.preamble_bytes = 1; }), "preamble_bytes");
  expect_rejected(with([](GfskSettings& s) { s.preamble_bytes = 65; }), "preamble_bytes");
  expect_rejected(with([](GfskSettings& s) { s.max_payload_bytes = 0; }), "max_payload_bytes");
  expect_rejected(with([](GfskSettings& s) { s.max_payload_bytes = 65536; }), "max_payload_bytes");

  EXPECT_NO_THROW(make_gfsk_transceiver(with([](GfskSettings& s) {
    s.samples_per_symbol = 2;
    s.modulation_index = 1.0F;
    s.bandwidth_time = 0.0F;
    s.preamble_bytes = 2;
    s.max_payload_bytes = 1;
  })));
  EXPECT_NO_THROW(make_gfsk_transceiver(with([](GfskSettings& s) {
    s.samples_per_symbol = 32;
    s.bandwidth_time = 0.2F;
    s.preamble_bytes = 64;
    s.max_payload_bytes = 65535;
  })));
  EXPECT_NO_THROW(make_gfsk_transceiver(with([](GfskSettings& s) {
    s.samples_per_symbol = 3;
    s.bandwidth_time = 1.0F;
  })));
}

}  // namespace
}  // namespace rfsitl::phy
