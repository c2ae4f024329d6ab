// Front-end impairments against their definitions: the carrier offset's phase
// at absolute sample times (and an OFDM receiver's estimate of it through the
// channel), Wiener phase noise's variance growing linearly with the lag and
// continuous across ticks, the I/Q imbalance's image level, the DC offset,
// and the scenario's `channel.impairments` with its errors.
#include "rfsitl/channel/front_end.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "phy/ofdm/rates.hpp"
#include "phy/ofdm/receiver.hpp"
#include "phy/ofdm/waveform.hpp"
#include "rfsitl/channel/channel.hpp"
#include "rfsitl/common/geodesy.hpp"
#include "rfsitl/registry/sample_stage_registry.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"

namespace rfsitl::channel {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

FrontEnd receiver(const FrontEndSettings& s, double fs, std::size_t tick, std::uint64_t node = 0) {
  return FrontEnd(s, FrontEndSide::kReceive, fs, tick, 99, node);
}

/// Ones through `f` over `ticks` ticks: the rotation it applied, sample by sample.
std::vector<cf32> rotation(FrontEnd& f, std::size_t tick, std::size_t ticks) {
  std::vector<cf32> out;
  for (std::size_t k = 0; k < ticks; ++k) {
    const auto t0 = static_cast<SampleTime>(k * tick);
    f.advance(t0);
    std::vector<cf32> x(tick, cf32{1.0F, 0.0F});
    f.apply(t0, x);
    out.insert(out.end(), x.begin(), x.end());
  }
  return out;
}

TEST(FrontEnd, ACarrierOffsetTurnsThePhaseAtItsRateFromAbsoluteTime) {
  FrontEndSettings s;
  s.cfo_hz = 1234.5;
  FrontEnd f = receiver(s, 1e6, 100);
  EXPECT_EQ(f.offset_hz(), 1234.5);
  const std::vector<cf32> r = rotation(f, 100, 50);
  for (const std::size_t t : {0UL, 1UL, 99UL, 100UL, 4321UL, 4999UL}) {
    const double want = std::fmod(kTwoPi * 1234.5 * static_cast<double>(t) / 1e6, kTwoPi);
    EXPECT_NEAR(std::abs(std::complex<double>(r[t]) - std::polar(1.0, want)), 0.0, 1e-5) << t;
  }
  // A receiver that starts late in a tick sees the same samples.
  f.advance(4900);
  std::vector<cf32> late(60, cf32{1.0F, 0.0F});
  f.apply(4940, late);
  for (std::size_t t = 0; t < late.size(); ++t) EXPECT_EQ(late[t], r[4940 + t]) << t;
}

TEST(FrontEnd, NodesDrawTheirOwnOffsetsFromTheSpread) {
  FrontEndSettings s;
  s.cfo_hz = 100.0;
  s.cfo_spread_hz = 1000.0;
  double sum = 0.0;
  double square = 0.0;
  const int n = 2000;
  for (int i = 0; i < n; ++i) {
    const double o = receiver(s, 1e6, 10, static_cast<std::uint64_t>(i)).offset_hz() - 100.0;
    sum += o;
    square += o * o;
  }
  // Mean 0 +- 4 sigma / sqrt(n); standard deviation 1000 within 8 %.
  EXPECT_NEAR(sum / n, 0.0, 4.0 * 1000.0 / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(square / n), 1000.0, 80.0);
  EXPECT_EQ(receiver(s, 1e6, 10, 7).offset_hz(), receiver(s, 1e6, 10, 7).offset_hz());
}

TEST(FrontEnd, PhaseNoiseIsAWienerProcessOfTheLinewidthItsLevelGives) {
  // -80 dBc/Hz at 10 kHz: linewidth b = pi 1e8 1e-8 = 3.14 Hz; the phase's
  // variance over a lag of tau samples is 2 pi b tau / fs.
  FrontEndSettings s;
  s.phase_noise_dbc_hz = -80.0;
  s.phase_noise_offset_hz = 1e4;
  const double fs = 1e5;
  const std::size_t tick = 250;
  FrontEnd f = receiver(s, fs, tick);
  const std::vector<cf32> r = rotation(f, tick, 4000);  // 10 s
  const double b = std::numbers::pi * 1e8 * 1e-8;
  for (const std::size_t lag : {1UL, 37UL, 250UL, 2000UL}) {
    double var = 0.0;
    std::size_t n = 0;
    for (std::size_t t = 0; t + lag < r.size(); t += lag) {
      const double d =
          std::arg(std::complex<double>(r[t + lag]) * std::conj(std::complex<double>(r[t])));
      var += d * d;
      ++n;
    }
    var /= static_cast<double>(n);
    const double want = kTwoPi * b * static_cast<double>(lag) / fs;
    // n independent increments: the estimate's relative error is sqrt(2 / n).
    EXPECT_NEAR(var / want, 1.0, 4.0 * std::sqrt(2.0 / static_cast<double>(n))) << lag;
  }
  // No jump at tick boundaries: the step across one is like any other step.
  double across = 0.0;
  for (std::size_t k = 1; k < 4000; ++k) {
    const double d = std::arg(std::complex<double>(r[k * tick]) *
                              std::conj(std::complex<double>(r[k * tick - 1])));
    across += d * d;
  }
  EXPECT_NEAR(across / 3999.0 / (kTwoPi * b / fs), 1.0, 4.0 * std::sqrt(2.0 / 3999.0));
}

TEST(FrontEnd, IqImbalancePutsAnImageAtTheLevelTheModelGives) {
  FrontEndSettings s;
  s.iq_imbalance_db = 0.5;
  s.iq_imbalance_deg = 2.0;
  FrontEnd f = receiver(s, 1e6, 1000);
  f.advance(0);
  // A tone at +fs/8 over 1000 samples (125 whole cycles).
  std::vector<cf32> x(1000);
  for (std::size_t t = 0; t < x.size(); ++t) {
    const auto v = std::polar(1.0, kTwoPi * static_cast<double>(t) / 8.0);
    x[t] = {static_cast<float>(v.real()), static_cast<float>(v.imag())};
  }
  f.apply(0, x);
  std::complex<double> at_plus = 0.0;
  std::complex<double> at_minus = 0.0;
  for (std::size_t t = 0; t < x.size(); ++t) {
    at_plus += std::complex<double>(x[t]) * std::polar(1.0, -kTwoPi * static_cast<double>(t) / 8.0);
    at_minus += std::complex<double>(x[t]) * std::polar(1.0, kTwoPi * static_cast<double>(t) / 8.0);
  }
  // Image rejection: (1 + g^2 + 2 g cos p) / (1 + g^2 - 2 g cos p).
  const double g = std::pow(10.0, 0.5 / 20.0);
  const double c = std::cos(2.0 * std::numbers::pi / 180.0);
  const double irr_db =
      10.0 * std::log10((1.0 + g * g + 2.0 * g * c) / (1.0 + g * g - 2.0 * g * c));
  EXPECT_NEAR(10.0 * std::log10(std::norm(at_plus) / std::norm(at_minus)), irr_db, 0.01);
  EXPECT_GT(irr_db, 25.0);  // about 30 dB, a typical receiver's
  EXPECT_LT(irr_db, 35.0);
}

TEST(FrontEnd, ADcOffsetIsAddedAtItsLevel) {
  FrontEndSettings s;
  s.dc_offset = 0.25;
  FrontEnd f = receiver(s, 1e6, 64);
  f.advance(0);
  std::vector<cf32> x(64, cf32{});
  f.apply(0, x);
  for (const cf32 v : x) EXPECT_NEAR(std::abs(v), 0.25, 1e-6);
  EXPECT_NEAR(std::arg(x[0]), std::numbers::pi / 4.0, 1e-6);
}

/// An OFDM PPDU from node 0 to node 1 through a channel whose receivers have
/// `rx` impairments: the receiver's carrier estimate, rad/sample.
std::optional<double> ofdm_cfo_estimate(const FrontEndSettings& rx) {
  const double fs = 20e6;
  const std::size_t tick = 400;
  const GeodeticPosition origin{43.0, -78.8, 0.0};
  SampleChain receive;
  receive.push_back(find_sample_stage("impairments")
                        ->make(front_end_fields().settings_of(rx),
                               SampleStageContext{SampleSide::kReceive, 2, fs, tick, 3, 0}));
  Channel ch(2, std::make_shared<LinkBudget>(0.0, std::vector<std::unique_ptr<GainStage>>{}),
             origin, ChannelConfig{1e-4, false, 3, fs, tick}, {}, std::move(receive));
  ch.matrix().set_position(0, local_to_ecef({0.0, 0.0, 0.0}, origin));
  ch.matrix().set_position(1, local_to_ecef({10.0, 0.0, 0.0}, origin));
  const std::vector<std::uint8_t> psdu(100, 0x5A);
  std::vector<cf32> air(tick, cf32{});
  std::vector<cf32> ppdu = phy::ofdm::build_ppdu(psdu, *phy::ofdm::rate_from_mbps(6), 0x5D, false);
  double power = 0.0;
  for (const cf32 v : ppdu) power += std::norm(v);
  const auto scale = static_cast<float>(std::sqrt(static_cast<double>(ppdu.size()) / power));
  for (cf32& v : ppdu) v *= scale;  // unit power: 40 dB above the noise
  air.insert(air.end(), ppdu.begin(), ppdu.end());
  air.resize((air.size() / tick + 3) * tick, cf32{});
  std::optional<double> estimate;
  // The PSDU carries no FCS of its own: a decoded SIGNAL field is enough.
  auto rxr = phy::ofdm::make_ofdm_receiver(
      [&](const phy::ofdm::DecodedPpdu& d) { estimate = d.cfo_rad_per_sample; });
  Channel::Scratch scratch;
  std::vector<cf32> y(tick);
  for (std::size_t k = 0; k * tick < air.size(); ++k) {
    const std::vector<Transmission> on{{0, air.data() + k * tick}};
    ch.on_air(static_cast<SampleTime>(k * tick), on);
    ch.begin_tick(static_cast<SampleTime>(k * tick), true);
    ch.receive(1, 0, y, scratch);
    rxr->push(y);
  }
  return estimate;
}

TEST(FrontEnd, AnOfdmReceiverEstimatesTheCarrierOffsetThroughTheChannel) {
  for (const double cfo : {50e3, -120e3}) {
    FrontEndSettings rx;
    rx.cfo_hz = cfo;
    const auto est = ofdm_cfo_estimate(rx);
    ASSERT_TRUE(est.has_value()) << cfo;
    EXPECT_NEAR(*est, kTwoPi * cfo / 20e6, 0.02 * kTwoPi * std::abs(cfo) / 20e6) << cfo;
  }
}

TEST(FrontEnd, TheScenarioReadsImpairmentsAndRefusesBadOnesWithTheirLine) {
  const std::string ok =
      "time: {mode: virtual, duration_s: 0.1}\n"
      "channel:\n  impairments:\n    rx: {cfo_hz: 200, iq_imbalance_db: 0.5}\n"
      "    tx: {dc_offset: 0.01}\n"
      "nodes: [{id: 1, position: {x: 0, y: 0, z: 0}}, {id: 2, position: {x: 5, y: 0, z: 0}}]\n";
  const scenario::Scenario s = scenario::parse_scenario(ok, "imp.yaml");
  // The short form is a leading `impairments` sample stage on each side.
  ASSERT_EQ(s.channel.rx_stages.size(), 1U);
  ASSERT_EQ(s.channel.tx_stages.size(), 1U);
  EXPECT_EQ(s.channel.rx_stages[0].type, "impairments");
  const FrontEndSettings rx = front_end_fields().build(s.channel.rx_stages[0].settings);
  const FrontEndSettings tx = front_end_fields().build(s.channel.tx_stages[0].settings);
  EXPECT_EQ(rx.cfo_hz, 200.0);
  EXPECT_EQ(rx.iq_imbalance_db, 0.5);
  EXPECT_EQ(tx.dc_offset, 0.01);
  const std::string bad =
      "time: {mode: virtual, duration_s: 0.1}\n"
      "channel:\n  impairments:\n    rx: {cfo_hz: 2e9}\n"
      "nodes: [{id: 1, position: {x: 0, y: 0, z: 0}}]\n";
  try {
    (void)scenario::parse_scenario(bad, "imp.yaml");
    FAIL() << "accepted cfo_hz 2e9";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("imp.yaml:4"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("cfo_hz"), std::string::npos) << e.what();
  }
  const std::string unknown = "channel:\n  impairments:\n    rx: {cfo: 1}\nnodes: [{id: 1}]\n";
  EXPECT_THROW((void)scenario::parse_scenario(unknown, "imp.yaml"), std::exception);
}

}  // namespace
}  // namespace rfsitl::channel
