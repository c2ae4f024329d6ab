// Sample stages: the channel's chain (transmit stages on copies before the
// mix, the noise first on the receive side and the listed stages after it,
// advanced once per tick), the engine running every receiver when a stage
// makes skipping inexact, and the adc stage against its definition.
#include "rfsitl/channel/sample_stage.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <set>
#include <vector>

#include "engine_run.hpp"
#include "rfsitl/channel/channel.hpp"
#include "rfsitl/channel/noise_source.hpp"
#include "rfsitl/channel/stages/path_loss.hpp"
#include "rfsitl/common/geodesy.hpp"
#include "rfsitl/registry/sample_stage_registry.hpp"
#include "spy_sample_stage.hpp"

namespace rfsitl::channel {
namespace {

using testing::SpySampleStage;

const GeodeticPosition kOrigin{43.0, -78.8, 0.0};
constexpr std::size_t kTick = 64;

/// Two nodes 3 m apart through the paper's model (exponent 1), with the
/// given chains; returns the spies' addresses through `tx_spy`/`rx_spy`.
Channel pair(double noise_variance, SampleChain tx, SampleChain rx) {
  Channel ch(2, make_paper_budget(1.0), kOrigin,
             ChannelConfig{noise_variance, false, 7, 1e6, kTick}, std::move(tx), std::move(rx));
  ch.matrix().set_position(0, local_to_ecef({0.0, 0.0, 0.0}, kOrigin));
  ch.matrix().set_position(1, local_to_ecef({3.0, 0.0, 0.0}, kOrigin));
  return ch;
}

std::vector<cf32> receive_tick(Channel& ch, SampleTime start, const std::vector<cf32>& x) {
  const std::vector<Transmission> on{{0, x.data()}};
  ch.on_air(start, on);
  ch.begin_tick(start, true);
  std::vector<cf32> y(kTick);
  Channel::Scratch scratch;
  ch.receive(1, 0, y, scratch);
  return y;
}

TEST(SampleStages, ATransmitStageActsOnACopyBeforeTheMix) {
  const std::vector<cf32> x(kTick, cf32{1.0F, 0.0F});
  Channel plain = pair(0.0, {}, {});
  SampleChain tx;
  auto spy = std::make_unique<SpySampleStage>(cf32{0.0F, 2.0F});  // x 2j
  const SpySampleStage* seen = spy.get();
  tx.push_back(std::move(spy));
  Channel staged = pair(0.0, std::move(tx), {});
  const std::vector<cf32> a = receive_tick(plain, 640, x);
  const std::vector<cf32> b = receive_tick(staged, 640, x);
  for (std::size_t t = 0; t < kTick; ++t) {
    EXPECT_NEAR(std::abs(b[t] - cf32{0.0F, 2.0F} * a[t]), 0.0, 1e-3 * std::abs(a[t])) << t;
  }
  EXPECT_EQ(x[0], (cf32{1.0F, 0.0F}));  // the transmitter's own samples are untouched
  ASSERT_EQ(seen->applies.size(), 1U);
  EXPECT_EQ(seen->applies[0].node, 0U);
  EXPECT_EQ(seen->applies[0].first_sample, 640);
  ASSERT_EQ(seen->advances.size(), 1U);
  EXPECT_TRUE(seen->advances[0].applies);
}

TEST(SampleStages, ReceiveStagesComeAfterTheNoiseAndAdvanceEveryTick) {
  SampleChain rx;
  auto zero = std::make_unique<SpySampleStage>(cf32{});  // x 0: nothing survives it
  const SpySampleStage* seen = zero.get();
  rx.push_back(std::move(zero));
  Channel ch = pair(1e-6, {}, std::move(rx));
  Channel::Scratch scratch;
  std::vector<cf32> y(kTick - 10, cf32{5.0F, 5.0F});
  for (SampleTime start = 0; start < 3 * static_cast<SampleTime>(kTick); start += kTick) {
    ch.on_air(start, {});
    ch.begin_tick(start, start != 0);  // no receiver runs in the first tick
  }
  ch.receive(1, 10, y, scratch);
  for (const cf32 v : y) ASSERT_EQ(v, cf32{});  // had it run before the noise, noise would remain
  ASSERT_EQ(seen->advances.size(), 3U);
  EXPECT_FALSE(seen->advances[0].applies);
  EXPECT_TRUE(seen->advances[2].applies);
  EXPECT_EQ(seen->advances[2].tick_start, 128);
  ASSERT_EQ(seen->applies.size(), 1U);
  EXPECT_EQ(seen->applies[0].first_sample, 138);  // absolute: the tick's start + first
  EXPECT_EQ(seen->applies[0].samples, kTick - 10);
}

TEST(SampleStages, OneStageThatMakesSkippingInexactTurnsSkippingOff) {
  SampleChain exact;
  exact.push_back(std::make_unique<SpySampleStage>());
  EXPECT_TRUE(pair(1e-6, {}, std::move(exact)).skipping_exact());
  SampleChain mixed;
  mixed.push_back(std::make_unique<SpySampleStage>());
  mixed.push_back(std::make_unique<SpySampleStage>(cf32{1.0F, 0.0F}, false));
  EXPECT_FALSE(pair(1e-6, {}, std::move(mixed)).skipping_exact());
}

/// A registered stage that changes nothing but says skipping is inexact.
const SampleStageComponent& inexact_component() {
  static const SampleStageComponent c = [] {
    SampleStageComponent out{
        config::ComponentInfo{"sample", "test_inexact", "a test double", {}, {}},
        [](const config::Settings&, const SampleStageContext&) {
          return std::make_unique<SpySampleStage>(cf32{1.0F, 0.0F}, false);
        }};
    sample_stage_registry().add(out);
    return out;
  }();
  return c;
}

TEST(SampleStages, TheEngineRunsEveryReceiverWhenAStageMakesSkippingInexact) {
  const std::vector<testing::NodeSpec> nodes{
      {1, LocalPosition{0, 0, 0}}, {2, LocalPosition{5, 0, 0}}, {3, LocalPosition{0, 5, 0}}};
  scenario::Scenario s = testing::make_scenario(nodes, 0.02);
  s.traffic.push_back(testing::frame_at(0.002, 1, 2, 40));
  const testing::RunResult skipping = testing::run_engine(s);
  EXPECT_GT(skipping.status.receiver_ticks_skipped, 0U);
  s.channel.rx_stages.push_back({inexact_component().info.name, {}});
  const testing::RunResult all = testing::run_engine(s);
  EXPECT_EQ(all.status.receiver_ticks_skipped, 0U);
  EXPECT_EQ(all.counters[0].delivered, 1U);
}

std::unique_ptr<SampleStage> adc(std::uint64_t bits, double full_scale_db) {
  const SampleStageComponent* c = find_sample_stage("adc");
  EXPECT_NE(c, nullptr);
  config::Settings s = c->info.defaults();
  s.set("bits", bits);
  s.set("full_scale_db", full_scale_db);
  c->info.validate(s);
  return c->make(s, SampleStageContext{SampleSide::kReceive, 1, 1e6, kTick, 1, 0});
}

TEST(AdcStage, ClipsAtFullScaleAndQuantizesToTwoToTheBitsMidRiseLevels) {
  const auto stage = adc(4, 0.0);  // A = 1, q = 2 / 16
  const float q = 2.0F / 16.0F;
  std::vector<cf32> ramp;
  for (int k = -2000; k < 2000; ++k) {
    // [-2, 2), beyond full scale both ways, never on a level boundary (m / 8)
    const float v = (static_cast<float>(k) + 0.5F) / 1000.0F;
    ramp.push_back({v, -v});
  }
  std::vector<cf32> out = ramp;
  stage->apply(0, 0, out);
  std::set<float> levels;
  for (std::size_t t = 0; t < ramp.size(); ++t) {
    const float v = ramp[t].real();
    levels.insert(out[t].real());
    EXPECT_EQ(out[t].imag(), -out[t].real()) << v;  // I and Q alike (mid-rise is symmetric)
    if (v >= 1.0F) {
      EXPECT_FLOAT_EQ(out[t].real(), 1.0F - q / 2.0F) << v;
    } else if (v < -1.0F) {
      EXPECT_FLOAT_EQ(out[t].real(), -1.0F + q / 2.0F) << v;
    } else {
      EXPECT_LE(std::abs(out[t].real() - v), q / 2.0F + 1e-6F) << v;
    }
  }
  EXPECT_EQ(levels.size(), 16U);
  EXPECT_EQ(levels.count(0.0F), 0U);
  EXPECT_TRUE(stage->keeps_skipping_exact());
}

TEST(AdcStage, QuantizationNoiseIsAStepSquaredOverTwelvePerBranch) {
  const auto stage = adc(8, 20.0);  // A = 10 noise RMS: nothing of unit noise clips (10 sigma)
  const double q = 2.0 * 10.0 / 256.0;
  std::vector<cf32> x(1 << 16, cf32{});
  NoiseSource(3, 0, 1.0F).add_to(x, 0);
  std::vector<cf32> y = x;
  stage->apply(0, 0, y);
  double error = 0.0;
  for (std::size_t t = 0; t < x.size(); ++t) error += std::norm(y[t] - x[t]);
  error /= static_cast<double>(x.size());
  EXPECT_NEAR(error, 2.0 * q * q / 12.0, 0.05 * 2.0 * q * q / 12.0);
}

}  // namespace
}  // namespace rfsitl::channel
