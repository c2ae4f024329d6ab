// ChannelMatrix::power_gain_at, the power a link delivers at a moment with the
// time-varying stages included: power_gain() exactly without them; with
// Rayleigh fading, power_gain() times an exponential variable of mean 1 over
// many links and moments; for a dispersive link the sum of its paths' powers,
// each path faded on its own. And the engine hands it to the dashboard
// (Engine::link_gains): with fading the gains change with time alone, at most
// every 100 ms of virtual time; without, they stay the large-scale ones.
// Fixed seeds, so nothing flakes; the bounds are 4 standard deviations of a
// correct implementation on a fresh seed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "engine_run.hpp"
#include "rfsitl/channel/channel_matrix.hpp"
#include "rfsitl/common/geodesy.hpp"
#include "rfsitl/config/settings.hpp"
#include "rfsitl/engine/engine_observer.hpp"
#include "rfsitl/position/source/position_source.hpp"
#include "rfsitl/registry/channel_stage_registry.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"
#include "stage_test_support.hpp"

namespace rfsitl::channel {
namespace {

const GeodeticPosition kOrigin{43.0, -78.8, 0.0};
constexpr double kFs = 1e6;

std::unique_ptr<GainStage> make(const std::string& type, const config::Settings& s = {}) {
  return rfsitl::testing::make_stage(type, s, kFs, 29);
}

config::Settings free_space() {
  config::Settings s;
  s.set("model", config::Value(std::string("free_space")));
  return s;
}

/// Two taps of equal power 3 us apart: whole samples at 1 Msps.
config::Settings two_taps() {
  return rfsitl::testing::multipath_taps({{0.0, 0.0}, {3000.0, 0.0}});
}

/// `n` nodes on a grid 7 m apart at 10 m up, each moving at 10 m/s on a
/// heading of its own (so that half a second later, 40 wavelengths on at
/// 2.4 GHz, every link's fading is a fresh draw), the last one without a
/// position when `one_unknown`.
ChannelMatrix grid(std::size_t n, std::vector<std::unique_ptr<GainStage>> stages,
                   bool one_unknown = false) {
  ChannelMatrix m(n, std::make_shared<LinkBudget>(0.0, std::move(stages)), kOrigin, kFs);
  for (std::size_t i = 0; i < n; ++i) {
    if (one_unknown && i + 1 == n) break;
    const auto x = static_cast<double>(i % 6);
    const auto y = static_cast<double>(i / 6);
    m.set_position(i, local_to_ecef({7.0 * x, 7.0 * y, 10.0}, kOrigin));
    const double heading = 2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n);
    m.set_velocity(i, {10.0 * std::cos(heading), 10.0 * std::sin(heading), 0.0});
  }
  return m;
}

constexpr double kMoments[] = {0.0, 0.5, 1.0, 1.5, 2.0};

TEST(PowerGainAt, WithoutTimeVaryingStagesItIsPowerGainAtEveryMoment) {
  std::vector<std::unique_ptr<GainStage>> flat;
  flat.push_back(make("path_loss", free_space()));
  std::vector<std::unique_ptr<GainStage>> dispersive;
  dispersive.push_back(make("path_loss", free_space()));
  dispersive.push_back(make("multipath", two_taps()));
  for (auto* stages : {&flat, &dispersive}) {
    const ChannelMatrix m = grid(7, std::move(*stages), true);
    ASSERT_FALSE(m.time_varying());
    for (std::size_t tx = 0; tx < m.size(); ++tx) {
      for (std::size_t rx = 0; rx < m.size(); ++rx) {
        for (const double t : kMoments) {
          EXPECT_EQ(m.power_gain_at(tx, rx, t), m.power_gain(tx, rx))
              << m.dispersive() << " " << tx << " -> " << rx << " at " << t;
        }
      }
    }
  }
}

TEST(PowerGainAt, WithRayleighFadingItIsPowerGainTimesAnExponentialOfMeanOne) {
  // 30 x 29 links at 5 moments: 4350 draws of |h|^2, exponential with mean 1
  // (E|h|^2 = 1 for any number of sinusoids): the mean within 4 / sqrt(4350)
  // = 0.061, and P(|h|^2 < 1/2) = 1 - exp(-1/2) = 0.393 within
  // 4 sqrt(0.393 x 0.607 / 4350) = 0.030.
  std::vector<std::unique_ptr<GainStage>> stages;
  stages.push_back(make("path_loss", free_space()));
  stages.push_back(make("fading"));
  const ChannelMatrix m = grid(30, std::move(stages));
  ASSERT_TRUE(m.time_varying());
  double sum = 0.0;
  std::size_t below_half = 0;
  std::size_t draws = 0;
  for (std::size_t tx = 0; tx < m.size(); ++tx) {
    for (std::size_t rx = 0; rx < m.size(); ++rx) {
      if (tx == rx) continue;
      ASSERT_GT(m.power_gain(tx, rx), 0.0F);
      for (const double t : kMoments) {
        const double ratio = m.power_gain_at(tx, rx, t) / m.power_gain(tx, rx);
        // A link of one path: the faded coefficient's power.
        EXPECT_FLOAT_EQ(m.power_gain_at(tx, rx, t), std::norm(m.coefficient_at(tx, rx, t)));
        sum += ratio;
        below_half += ratio < 0.5 ? 1 : 0;
        ++draws;
      }
    }
  }
  const auto n = static_cast<double>(draws);
  EXPECT_NEAR(sum / n, 1.0, 0.061);
  EXPECT_NEAR(static_cast<double>(below_half) / n, 1.0 - std::exp(-0.5), 0.030);
}

TEST(PowerGainAt, FadingChangesWithTimeOnlyAsTheEndsMove) {
  // The fading field is one of positions: nodes at rest keep their fade,
  // moving ones do not.
  std::vector<std::unique_ptr<GainStage>> stages;
  stages.push_back(make("path_loss", free_space()));
  stages.push_back(make("fading"));
  ChannelMatrix m = grid(4, std::move(stages));
  EXPECT_NE(m.power_gain_at(0, 1, 0.0), m.power_gain_at(0, 1, 0.5));
  for (std::size_t i = 0; i < m.size(); ++i) m.set_velocity(i, {});
  EXPECT_EQ(m.power_gain_at(0, 1, 0.0), m.power_gain_at(0, 1, 0.5));
}

TEST(PowerGainAt, ADispersiveLinkDeliversTheSumOfItsPathsPowersEachFadedOnItsOwn) {
  // Unit-gain links of two equal taps behind Rayleigh fading: each tap's power
  // is (1/2) |h_p|^2 with independent h_p, so the total has mean 1 and
  // variance 1/2; over 20 x 19 links at 5 moments, the mean within
  // 4 sqrt(0.5 / 1900) = 0.065. Path 0's fade applied to the total (what
  // coefficient_at gives) would have variance 1 and differ on most links.
  std::vector<std::unique_ptr<GainStage>> stages;
  stages.push_back(make("multipath", two_taps()));
  stages.push_back(make("fading"));
  const ChannelMatrix m = grid(20, std::move(stages));
  ASSERT_TRUE(m.dispersive());
  ASSERT_TRUE(m.time_varying());
  double sum = 0.0;
  std::size_t unlike_path_zero = 0;
  std::size_t draws = 0;
  for (std::size_t tx = 0; tx < m.size(); ++tx) {
    for (std::size_t rx = 0; rx < m.size(); ++rx) {
      if (tx == rx) continue;
      const LinkResponse& r = m.response(tx, rx);
      ASSERT_EQ(r.path_gains.size(), 2U);
      EXPECT_NEAR(std::norm(r.path_gains[0]) + std::norm(r.path_gains[1]), m.power_gain(tx, rx),
                  1e-5);
      for (const double t : kMoments) {
        double want = 0.0;
        for (std::size_t p = 0; p < 2; ++p) {
          want += std::norm(std::complex<double>(r.path_gains[p]) * m.fading_at(tx, rx, t, p));
        }
        const double got = m.power_gain_at(tx, rx, t);
        EXPECT_NEAR(got, want, 1e-5 * want) << tx << " -> " << rx << " at " << t;
        const double path_zero = std::norm(m.coefficient_at(tx, rx, t));
        unlike_path_zero += std::abs(path_zero - want) > 0.1 * want ? 1 : 0;
        sum += got;
        ++draws;
      }
    }
  }
  EXPECT_NEAR(sum / static_cast<double>(draws), 1.0, 0.065);
  EXPECT_GT(unlike_path_zero, draws / 2);
}

}  // namespace
}  // namespace rfsitl::channel

namespace rfsitl::testing {
namespace {

/// Three nodes at rest; node 1 is told once that it moves east at 10 m/s
/// (a velocity without a position: nothing moves, the fading follows it).
scenario::Scenario resting_trio(bool fading) {
  const std::string yaml =
      std::string(
          "time: {mode: virtual, duration_s: 1.0, sample_rate_hz: 1e6, tick_samples: 1000}\n"
          "channel:\n  stages: [{type: path_loss, model: free_space}") +
      (fading ? ", {type: fading}" : "") +
      "]\n"
      "engine: {threads: 1}\n"
      "nodes:\n  - {id: 1, position: {x: 0, y: 0, z: 10}}\n"
      "  - {id: 2, position: {x: 40, y: 0, z: 10}}\n"
      "  - {id: 3, position: {x: 0, y: 30, z: 10}}\n";
  return scenario::parse_scenario(yaml, "gain_at.yaml");
}

/// Reads the engine's published gains every tick (from the engine thread,
/// as the dashboard's thread would at any time) and keeps each new set.
class GainWatcher final : public engine::EngineObserver {
 public:
  void on_frame_event(const engine::FrameEvent&) override {}
  bool wants_samples(std::size_t node, SampleTime, std::size_t) const override { return node == 0; }
  void on_rx_samples(std::size_t, SampleTime time, std::span<const cf32>) override {
    std::vector<float> gains = engine->link_gains();
    if (seen.empty() || gains != seen.back().second) seen.emplace_back(time, std::move(gains));
  }
  engine::Engine* engine = nullptr;
  std::vector<std::pair<SampleTime, std::vector<float>>> seen;
};

std::vector<std::pair<SampleTime, std::vector<float>>> published(bool fading) {
  GainWatcher watcher;
  RunSetup setup;
  setup.observers = {&watcher};
  setup.before = [&watcher](engine::Engine& e) {
    watcher.engine = &e;
    e.report(0, position::StateReport{std::nullopt, position::Velocity{10.0, 0.0, 0.0}, {}});
  };
  run_engine(resting_trio(fading), setup);
  return watcher.seen;
}

TEST(EngineLinkGains, WithFadingTheyChangeWithTimeAloneAtMostEvery100Ms) {
  const auto seen = published(true);
  const auto flat = published(false);
  // One second: a set at the start, then one per 100 ms.
  ASSERT_GE(seen.size(), 9U);
  EXPECT_LE(seen.size(), 11U);
  for (std::size_t k = 1; k < seen.size(); ++k) {
    EXPECT_GE(seen[k].first - seen[k - 1].first, 100'000) << k;
  }
  // Node 1's links fade as it (virtually) moves: 9 draws of an exponential
  // variable span more than 3 dB. Links 2 <-> 3 rest: their fade holds, and
  // it is not the large-scale gain that a run without fading publishes.
  ASSERT_EQ(flat.size(), 1U);
  const std::vector<float>& large_scale = flat.front().second;
  ASSERT_EQ(large_scale.size(), 9U);
  float lo = seen.front().second[1];
  float hi = lo;
  for (const auto& [time, gains] : seen) {
    ASSERT_EQ(gains.size(), 9U);
    lo = std::min(lo, gains[1]);
    hi = std::max(hi, gains[1]);
    EXPECT_EQ(gains[1 * 3 + 2], seen.front().second[1 * 3 + 2]);
  }
  EXPECT_GT(hi / lo, 2.0F);
  EXPECT_GT(std::abs(seen.front().second[1 * 3 + 2] / large_scale[1 * 3 + 2] - 1.0F), 1e-3F);
}

}  // namespace
}  // namespace rfsitl::testing
