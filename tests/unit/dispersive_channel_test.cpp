// Dispersive links through the channel as the engine calls it: the delay
// stage's d / c seen in the received samples, tails that reach a receiver in
// the ticks after their transmitter fell silent, the multipath stage's taps
// (TR 38.901 profiles' delay spreads, given taps, reciprocity), and taps that
// fade independently behind a fading stage.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <string>
#include <vector>

#include "rfsitl/channel/channel.hpp"
#include "rfsitl/channel/radio.hpp"
#include "rfsitl/channel/stages/multipath.hpp"
#include "rfsitl/common/geodesy.hpp"
#include "rfsitl/config/settings.hpp"
#include "rfsitl/registry/channel_stage_registry.hpp"

#include "stage_test_support.hpp"

namespace rfsitl::channel {
namespace {

using rfsitl::testing::refused_key;

const GeodeticPosition kOrigin{43.0, -78.8, 0.0};

std::unique_ptr<GainStage> make(const std::string& type, const config::Settings& s,
                                double sample_rate_hz) {
  return rfsitl::testing::make_stage(type, s, sample_rate_hz, 11);
}

/// Nodes on the east axis at `east_m`, unit-gain links but for the stages,
/// noise at -100 dB below them (front-end gain 1e5).
Channel line_of(const std::vector<double>& east_m, std::vector<std::unique_ptr<GainStage>> stages,
                double fs, std::size_t tick) {
  Channel ch(east_m.size(), std::make_shared<LinkBudget>(0.0, std::move(stages)), kOrigin,
             ChannelConfig{1e-10, false, 5, fs, tick});
  for (std::size_t i = 0; i < east_m.size(); ++i) {
    ch.matrix().set_position(i, local_to_ecef({east_m[i], 0.0, 0.0}, kOrigin));
  }
  return ch;
}

/// Node 0 sends `burst` in tick 0 and is silent after; node 1's input over
/// `ticks` ticks, and whether it heard a signal in each.
struct Heard {
  std::vector<cf32> y;
  std::vector<bool> signal;
};

Heard listen(Channel& ch, const std::vector<cf32>& burst, std::size_t tick, std::size_t ticks) {
  Heard h;
  Channel::Scratch scratch;
  std::vector<cf32> y(tick);
  for (std::size_t k = 0; k < ticks; ++k) {
    const std::vector<Transmission> on{{0, burst.data()}};
    ch.on_air(static_cast<SampleTime>(k * tick),
              k == 0 ? std::span(on) : std::span<Transmission>{});
    h.signal.push_back(ch.hears_signal(1));
    ch.receive(1, 0, y, scratch);
    h.y.insert(h.y.end(), y.begin(), y.end());
  }
  return h;
}

std::size_t loudest(const std::vector<cf32>& y) {
  return static_cast<std::size_t>(
      std::max_element(y.begin(), y.end(),
                       [](cf32 a, cf32 b) { return std::norm(a) < std::norm(b); }) -
      y.begin());
}

TEST(DelayStage, TheReceivedSamplesAreLateByTheDistanceOverTheSpeedOfLight) {
  // 20 Msps, 3 km and 7.5 km: 200.1 and 500.3 samples, ticks of 64 samples, so
  // the pulse arrives three and seven ticks after its transmitter fell silent.
  const double fs = 20e6;
  for (const double d : {3000.0, 7500.0}) {
    std::vector<std::unique_ptr<GainStage>> stages;
    stages.push_back(make("delay", {}, fs));
    Channel ch = line_of({0.0, d}, std::move(stages), fs, 64);
    std::vector<cf32> pulse(64, cf32{});
    pulse[5] = cf32{1.0F, 0.0F};
    const Heard h = listen(ch, pulse, 64, 12);
    const double want = 5.0 + d / kSpeedOfLight * fs;
    EXPECT_NEAR(static_cast<double>(loudest(h.y)), want, 1.0) << d;
    // The whole pulse arrived, across tick boundaries, long after node 0 fell
    // silent: its energy is the response's times the front end's gain squared
    // (1e10). (The response passes a little less than all of a full-band
    // impulse's energy, 0.93 at 0.35 samples: the window rolls off towards fs / 2.)
    double taps = 0.0;
    for (const cf32 v : ch.matrix().response(0, 1).taps) taps += std::norm(v);
    EXPECT_GT(taps, 0.9) << d;
    EXPECT_LE(taps, 1.0) << d;
    double energy = 0.0;
    for (const cf32 v : h.y) energy += std::norm(v);
    EXPECT_NEAR(energy / 1e10, taps, 1e-3) << d;
  }
}

TEST(DelayStage, ATailKeepsTheReceiverAwakeUntilItHasPassedAndNoLonger) {
  const double fs = 20e6;
  std::vector<std::unique_ptr<GainStage>> stages;
  stages.push_back(make("delay", {}, fs));
  // 3 km: the last lag is about 208 samples; node 0's signal ends at 64.
  Channel ch = line_of({0.0, 3000.0}, std::move(stages), fs, 64);
  const std::vector<cf32> burst(64, cf32{1.0F, 0.0F});
  const Heard h = listen(ch, burst, 64, 8);
  const std::uint32_t last = ch.matrix().response(0, 1).lags.back();
  for (std::size_t k = 0; k < h.signal.size(); ++k) {
    const bool reaches = 64 + static_cast<SampleTime>(last) > static_cast<SampleTime>(k * 64);
    EXPECT_EQ(h.signal[k], reaches) << "tick " << k;
  }
  EXPECT_FALSE(h.signal.back());
}

TEST(DelayStage, WholeSamplesMakeOneTapPerLink) {
  const double fs = 1e6;
  std::vector<std::unique_ptr<GainStage>> stages;
  config::Settings s;
  s.set("whole_samples", config::Value(true));
  stages.push_back(make("delay", s, fs));
  Channel ch = line_of({0.0, 1000.0}, std::move(stages), fs, 250);
  const LinkResponse& r = ch.matrix().response(0, 1);
  ASSERT_EQ(r.lags.size(), 1U);
  EXPECT_EQ(r.lags[0], 3U);  // 3.34 samples, rounded
}

TEST(MultipathStage, TheTdlProfilesHaveTheDelaySpreadTheyAreScaledTo) {
  // 38.901's normalised delays are in units of the RMS delay spread (the
  // tables give 1.0000 to four digits: a check of the transcribed values too).
  for (const auto p : {MultipathProfile::kTdlA, MultipathProfile::kTdlB, MultipathProfile::kTdlC}) {
    MultipathSettings s;
    s.profile = p;
    s.delay_spread_ns = 300.0;
    const auto paths = multipath::normalised_paths(multipath::profile_taps(s));
    double power = 0.0;
    for (const Path& q : paths) power += std::norm(q.gain);
    EXPECT_NEAR(power, 1.0, 1e-12);
    EXPECT_NEAR(multipath::rms_delay_spread_s(paths) * 1e9, 300.0, 300.0 * 0.001)
        << static_cast<int>(p);
  }
}

TEST(MultipathStage, GivenTapsAreTheReceivedImpulseResponseAndTheLinkIsReciprocal) {
  // 1 Msps; taps at 0, 2 and 5 us: whole samples, powers 0, -3, -6 dB.
  const double fs = 1e6;
  const config::Settings s =
      rfsitl::testing::multipath_taps({{0.0, 0.0}, {2000.0, -3.0}, {5000.0, -6.0}});
  std::vector<std::unique_ptr<GainStage>> stages;
  stages.push_back(make("multipath", s, fs));
  Channel ch = line_of({0.0, 10.0}, std::move(stages), fs, 16);
  std::vector<cf32> pulse(16, cf32{});
  pulse[3] = cf32{1.0F, 0.0F};
  const Heard h = listen(ch, pulse, 16, 2);
  const double total = 1.0 + std::pow(10.0, -0.3) + std::pow(10.0, -0.6);
  const double want[] = {1.0 / total, std::pow(10.0, -0.3) / total, std::pow(10.0, -0.6) / total};
  const std::size_t at[] = {3, 5, 8};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(std::norm(h.y[at[i]]) / 1e10, want[i], 1e-4) << i;
  }
  EXPECT_LT(std::norm(h.y[4]) / 1e10, 1e-6);
  const LinkResponse& ab = ch.matrix().response(0, 1);
  const LinkResponse& ba = ch.matrix().response(1, 0);
  EXPECT_EQ(ab.lags, ba.lags);
  EXPECT_EQ(ab.taps, ba.taps);
  // What the ledger and the dashboard see: the total power.
  EXPECT_NEAR(ch.matrix().power_gain(0, 1), 1.0, 1e-6);
}

TEST(MultipathStage, RefusesTapsWithoutTheTapsProfileAndTheReverse) {
  EXPECT_EQ(refused_key("multipath", "profile", config::Value(std::string("taps"))), "taps");
  EXPECT_EQ(refused_key("multipath", "delay_spread_ns", config::Value(0.5)), "delay_spread_ns");
  EXPECT_EQ(refused_key("multipath", "profile", config::Value(std::string("tdl_z"))), "profile");
}

TEST(MultipathFading, EachTapFadesOnItsOwnWithItsShareOfThePower) {
  // Two taps of equal power, 3 us apart at 1 Msps, Rayleigh fading after them:
  // over 40 x 39 links, each tap's mean power is 1/2 and the taps are
  // uncorrelated (|rho| < 4 / sqrt(1560) = 0.10, a 4-sigma bound).
  const double fs = 1e6;
  const config::Settings s = rfsitl::testing::multipath_taps({{0.0, 0.0}, {3000.0, 0.0}});
  std::vector<std::unique_ptr<GainStage>> stages;
  stages.push_back(make("multipath", s, fs));
  stages.push_back(make("fading", {}, fs));
  std::vector<double> east(40);
  for (std::size_t i = 0; i < east.size(); ++i) east[i] = 5.0 * static_cast<double>(i);
  Channel ch = line_of(east, std::move(stages), fs, 250);
  std::complex<double> cross = 0.0;
  double p0 = 0.0;
  double p1 = 0.0;
  std::size_t links = 0;
  for (std::size_t a = 0; a < east.size(); ++a) {
    for (std::size_t b = 0; b < east.size(); ++b) {
      if (a == b) continue;
      const LinkResponse& r = ch.matrix().response(a, b);
      ASSERT_EQ(r.path_gains.size(), 2U);
      const std::complex<double> h0 =
          std::complex<double>(r.path_gains[0]) * ch.matrix().fading_at(a, b, 0.0, 0);
      const std::complex<double> h1 =
          std::complex<double>(r.path_gains[1]) * ch.matrix().fading_at(a, b, 0.0, 1);
      cross += h0 * std::conj(h1);
      p0 += std::norm(h0);
      p1 += std::norm(h1);
      ++links;
    }
  }
  const auto n = static_cast<double>(links);
  EXPECT_NEAR(p0 / n, 0.5, 0.05);
  EXPECT_NEAR(p1 / n, 0.5, 0.05);
  EXPECT_LT(std::abs(cross) / std::sqrt(p0 * p1), 0.10);
}

}  // namespace
}  // namespace rfsitl::channel
