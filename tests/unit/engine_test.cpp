// The engine end to end with the real default PHY (GMSK): what only the real
// receiver can show (payloads through the modem, capture, noise, determinism
// and exact silence skipping with a real detector). The engine's own logic is
// tested on FakeTransceivers in engine_doubles_test.cpp.
#include "rfsitl/engine/engine.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "engine_run.hpp"
#include "rfsitl/registry/phy_registry.hpp"

namespace rfsitl::testing {
namespace {

using engine::LossReason;
using scenario::Scenario;
using scenario::TrafficItem;

const std::vector<NodeSpec> kPair{{1, LocalPosition{0, 0, 0}}, {2, LocalPosition{5, 0, 0}}};
const std::vector<NodeSpec> kTriangle{
    {1, LocalPosition{0, 0, 0}}, {2, LocalPosition{5, 0, 0}}, {3, LocalPosition{0, 4, 1}}};

TEST(Engine, ScheduledFrameIsDeliveredToDestinationSinkWithItsContents) {
  Scenario s = make_scenario(kPair, 0.01);
  s.traffic.push_back(frame_at(0.002, 1, 2, 80));
  const RunResult r = run_engine(s);
  ASSERT_EQ(r.deliveries.size(), 1U);
  const Delivery& d = r.deliveries.front();
  EXPECT_EQ(d.node, 1U);
  EXPECT_EQ(d.frame.src, 1);
  EXPECT_EQ(d.frame.dst, 2);
  ASSERT_EQ(d.frame.payload.size(), 80U);
  for (std::size_t b = 0; b < 80; ++b) EXPECT_EQ(d.frame.payload[b], b) << "byte " << b;
  // Goes on air at the 2 ms tick boundary; decoded within frame + receiver latency.
  const auto radio = phy::make_transceiver(s.phy.type, s.phy.settings);
  EXPECT_GE(d.tick_start, 2000);
  EXPECT_LE(d.tick_start,
            static_cast<SampleTime>(2000 + radio->frame_samples(80) + radio->rx_latency_samples()));
  EXPECT_EQ(r.counters[0].handed_in, 1U);
  EXPECT_EQ(r.counters[0].transmitted, 1U);
  EXPECT_EQ(r.counters[0].delivered, 1U);
  EXPECT_EQ(r.counters[0].lost_total(), 0U);
  EXPECT_EQ(r.counters[1].received, 1U);
  EXPECT_EQ(r.status.virtual_samples, 10000);
}

Scenario busy_triangle() {
  Scenario s = make_scenario(kTriangle, 0.04);
  s.traffic = {frame_at(0.000, 1, 2),     frame_at(0.001, 3, 2, 40),  // overlap at node 2
               frame_at(0.006, 2, 255),   frame_at(0.012, 3, 1, 200),
               frame_at(0.012, 1, 3, 10), frame_at(0.020, 2, 1, 1)};
  s.traffic.push_back(TrafficItem{0.025, 1, 3, 60, 3, 0.003});
  return s;
}

TEST(Engine, SameScenarioAndSeedGiveIdenticalDeliveriesAndCountersAnyThreadCount) {
  Scenario s = busy_triangle();
  const RunResult first = run_engine(s);
  const RunResult second = run_engine(s);
  EXPECT_GE(first.deliveries.size(), 5U);
  expect_same_outcome(first, second);
  s.engine.threads = 1;
  expect_same_outcome(first, run_engine(s));
  s.engine.threads = 3;
  expect_same_outcome(first, run_engine(s));
}

TEST(Engine, SkippingIdleReceiversChangesNoDeliveryOrCounter) {
  // Exact only if the real receiver finds nothing in noise alone: fed or not,
  // the ticks skipped must change nothing it decodes.
  for (std::size_t bytes : {10U, 80U}) {
    Scenario s = make_scenario(kTriangle, 0.04);
    s.traffic = collision_free_traffic(bytes);
    s.engine.skip_idle_receivers = true;
    const RunResult on = run_engine(s);
    s.engine.skip_idle_receivers = false;
    const RunResult off = run_engine(s);
    EXPECT_EQ(on.deliveries.size(), 6U) << bytes << " bytes";  // broadcast reaches two
    expect_same_outcome(on, off);
    EXPECT_GT(on.status.receiver_ticks_skipped, 0U);
    EXPECT_LT(on.status.receiver_ticks_run, off.status.receiver_ticks_run);
  }
}

TEST(Engine, MuchStrongerFrameIsCapturedAndWeakerOneLostToCollision) {
  Scenario s = make_scenario(
      {{1, LocalPosition{-2, 0, 0}}, {2, LocalPosition{0, 0, 0}}, {3, LocalPosition{40, 0, 0}}},
      0.01);
  s.channel.noise_variance = 1e-12;  // -120 dB: node 3 alone would be at +23 dB SNR
  s.traffic = {frame_at(0.002, 1, 2), frame_at(0.002, 3, 2)};
  const RunResult r = run_engine(s);
  ASSERT_EQ(r.deliveries.size(), 1U);
  EXPECT_EQ(r.deliveries.front().frame.src, 1);
  EXPECT_EQ(r.counters[0].delivered, 1U);
  EXPECT_EQ(r.counters[2].delivered, 0U);
  EXPECT_EQ(r.lost(2, LossReason::kCollision), 1U);
}

TEST(Engine, SharedNoiseSourceStillDelivers) {
  Scenario s = make_scenario(kTriangle, 0.015);
  s.channel.shared_noise = true;
  s.traffic = {frame_at(0.001, 1, 2), frame_at(0.006, 2, 255)};
  const RunResult r = run_engine(s);
  EXPECT_EQ(r.deliveries.size(), 3U);
  EXPECT_EQ(r.counters[0].delivered, 1U);
  EXPECT_EQ(r.counters[1].delivered, 1U);
  EXPECT_EQ(r.counters[0].received + r.counters[2].received, 2U);
}

}  // namespace
}  // namespace rfsitl::testing
