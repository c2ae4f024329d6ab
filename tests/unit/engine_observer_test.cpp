// The engine's observer interface: the frame events agree with the counters
// and come in order, a watched node's samples arrive every tick, and decodes
// carry constellations. Engine logic runs on FakeTransceivers (tests/support);
// the constellation needs the real PHY.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <vector>

#include "engine_run.hpp"
#include "fake_fleet.hpp"
#include "spy_observer.hpp"

namespace rfsitl::testing {
namespace {

using engine::FrameEventKind;
using engine::kNumLossReasons;
using engine::LossReason;
using Kind = SpyObserver::Kind;

/// Four nodes 20-35 m apart that talk at once now and then (collisions).
scenario::Scenario busy_scenario() {
  scenario::Scenario s;
  s.seed = 5;
  const double xs[] = {0, 20, 0, 25};
  const double ys[] = {0, 0, 30, 25};
  for (NodeId id = 1; id <= 4; ++id) {
    scenario::NodeConfig n;
    n.id = id;
    n.initial_position = LocalPosition{xs[id - 1], ys[id - 1], 10};
    s.nodes.push_back(n);
  }
  s.timing.mode = scenario::TimeMode::kVirtual;
  s.timing.duration_s = 0.4;
  s.engine.threads = 2;
  const auto add = [&](double at, NodeId src, NodeId dst, std::size_t size, unsigned repeat,
                       double every) {
    s.traffic.push_back(scenario::TrafficItem{at, src, dst, size, repeat, every});
  };
  add(0.01, 1, 2, 80, 25, 0.013);
  add(0.015, 4, 3, 120, 25, 0.011);
  add(0.02, 2, 4, 60, 25, 0.0097);
  add(0.03, 3, 255, 40, 15, 0.017);
  return s;
}

/// Fakes with 16 samples per byte: 80-byte frames (1380 samples) outlast a
/// 250-sample tick several times over, as the real PHY's do.
FakeFleet busy_fleet() {
  FakeConfig c;
  c.samples_per_byte = 16;
  c.rx_latency_samples = 30;
  return FakeFleet(c);
}

TEST(EngineObserver, FrameEventsAgreeWithEveryNodesCounters) {
  FakeFleet fleet = busy_fleet();
  SpyObserver spy;
  const RunResult r = run_engine(busy_scenario(), {fleet.factory(), {&spy}});
  std::map<std::pair<NodeId, FrameEventKind>, std::uint64_t> kinds;
  const auto count = [&](NodeId id, FrameEventKind k) { return kinds[std::make_pair(id, k)]; };
  std::map<std::pair<NodeId, LossReason>, std::uint64_t> reasons;
  std::map<std::uint32_t, std::vector<FrameEventKind>> by_serial;
  for (const auto& e : spy.events()) {
    ++kinds[{e.node, e.kind}];
    if (e.kind == FrameEventKind::kLost) ++reasons[{e.node, *e.reason}];
    if (e.kind != FrameEventKind::kHandedIn) by_serial[e.serial].push_back(e.kind);
  }
  std::uint64_t losses = 0;
  std::uint64_t deliveries = 0;
  for (std::size_t i = 0; i < r.counters.size(); ++i) {
    const auto& k = r.counters[i];
    const NodeId id = r.engine->node_ids()[i];
    EXPECT_EQ(count(id, FrameEventKind::kHandedIn), k.handed_in) << int{id};
    EXPECT_EQ(count(id, FrameEventKind::kTransmitted), k.transmitted) << int{id};
    EXPECT_EQ(count(id, FrameEventKind::kDelivered), k.delivered) << int{id};
    EXPECT_EQ(count(id, FrameEventKind::kReceived), k.received) << int{id};
    for (std::size_t reason = 0; reason < kNumLossReasons; ++reason) {
      EXPECT_EQ(reasons[std::make_pair(id, static_cast<LossReason>(reason))], k.lost[reason])
          << int{id} << " " << reason;
    }
    losses += k.lost_total();
    deliveries += k.delivered;
  }
  EXPECT_GT(losses, 0U);  // the scenario exercises losses as well as deliveries
  EXPECT_GT(deliveries, 0U);
  // Each transmission: transmitted first, then exactly one final outcome.
  for (const auto& [serial, seq] : by_serial) {
    ASSERT_FALSE(seq.empty());
    EXPECT_EQ(seq.front(), FrameEventKind::kTransmitted) << serial;
    const auto finals = std::count_if(seq.begin(), seq.end(), [](FrameEventKind k) {
      return k == FrameEventKind::kDelivered || k == FrameEventKind::kLost;
    });
    EXPECT_LE(finals, 1) << serial;
  }
}

TEST(EngineObserver, OneFramesCallbacksComeInOrderWithTheirTimes) {
  // A unicast delivered: handed in, transmitted, the receiver's decode (worker
  // thread), received, delivered. One lost: transmitted, lost with its reason.
  FakeConfig c;
  c.rx_latency_samples = 40;
  FakeFleet fleet(c);
  SpyObserver spy;
  scenario::Scenario s = make_scenario(
      {{1, LocalPosition{0, 0, 0}}, {2, LocalPosition{5, 0, 0}}, {3, std::nullopt}}, 0.006);
  s.traffic = {frame_at(0.0015, 1, 2, 80), frame_at(0.003, 2, 3, 10)};
  run_engine(s, {fleet.factory(), {&spy}});
  const auto tx = spy.events(Kind::kTransmitted);
  ASSERT_EQ(tx.size(), 2U);
  const auto first = spy.of_serial(tx[0].serial);
  ASSERT_EQ(first.size(), 3U);
  const auto handed = spy.events(Kind::kHandedIn);
  ASSERT_EQ(handed.size(), 2U);
  // Every decode with a valid header is shown, addressed to the node or not:
  // node 1 also hears node 2's frame to node 3.
  const auto decodes = spy.decodes();
  ASSERT_EQ(decodes.size(), 2U);
  EXPECT_EQ(decodes[1].node, 0U);
  EXPECT_EQ(decodes[1].tag.serial, tx[1].serial);
  const auto& d = decodes[0];
  EXPECT_EQ(d.node, 1U);
  EXPECT_EQ(d.tag.serial, tx[0].serial);
  EXPECT_TRUE(d.header_valid && d.payload_valid);
  EXPECT_EQ(d.payload.size(), 80U);
  // Sequence numbers: the order in which the engine called the observer.
  EXPECT_LT(handed[0].seq, first[0].seq);
  EXPECT_EQ(first[0].kind, Kind::kTransmitted);
  EXPECT_LT(first[0].seq, d.seq);
  EXPECT_EQ(first[1].kind, Kind::kReceived);
  EXPECT_LT(d.seq, first[1].seq);
  EXPECT_EQ(first[2].kind, Kind::kDelivered);
  // Handed in and sent at the 2000 tick; decoded at 2780, in that tick.
  EXPECT_EQ(handed[0].time, 2000);
  EXPECT_EQ(first[0].time, 2000);
  EXPECT_EQ(first[0].length_samples, 740U);
  EXPECT_EQ(d.time, 2000);
  EXPECT_EQ(first[1].time, 2000);
  EXPECT_EQ(first[1].node, 2);
  EXPECT_EQ(first[2].time, 2000);
  EXPECT_EQ(first[2].node, 1);
  const auto second = spy.of_serial(tx[1].serial);
  ASSERT_EQ(second.size(), 2U);
  EXPECT_EQ(second[0].kind, Kind::kTransmitted);
  EXPECT_EQ(second[1].kind, Kind::kLost);
  EXPECT_EQ(second[1].reason, LossReason::kBelowSensitivity);
  EXPECT_EQ(second[1].payload.size(), 10U);
}

TEST(EngineObserver, WatchedNodeGetsEveryTicksSamplesNoiseAtUnitPowerAndZerosWhileItSends) {
  scenario::Scenario s = busy_scenario();
  s.timing.duration_s = 0.2;
  FakeFleet fleet = busy_fleet();
  SpyObserver spy({0});  // node 1, which also transmits
  run_engine(s, {fleet.factory(), {&spy}});
  const auto seen = spy.samples();
  const std::size_t ticks = static_cast<std::size_t>(0.2 * 1e6 / s.timing.tick_samples);
  ASSERT_EQ(seen.size(), ticks);
  std::vector<double> power;
  for (std::size_t k = 0; k < ticks; ++k) {
    ASSERT_EQ(seen[k].node, 0U);
    ASSERT_EQ(seen[k].time, static_cast<SampleTime>(k * s.timing.tick_samples));
    ASSERT_EQ(seen[k].samples.size(), s.timing.tick_samples);
    power.push_back(seen[k].mean_power());
  }
  // Before any traffic (10 ms): pure noise at the front-end scale.
  double early = 0;
  for (std::size_t k = 0; k < 30; ++k) early += power[k];
  EXPECT_NEAR(early / 30, 1.0, 0.05);
  // While node 1 sends a whole tick its receiver is blanked: exactly zero.
  EXPECT_TRUE(std::any_of(power.begin(), power.end(), [](double p) { return p == 0.0; }));
  // And while others send to it, far above the noise.
  EXPECT_TRUE(std::any_of(power.begin(), power.end(), [](double p) { return p > 100.0; }));
}

TEST(EngineObserver, DecodesCarryTheirConstellation) {
  SpyObserver spy;
  run_engine(busy_scenario(), {{}, {&spy}});  // the real PHY
  std::vector<std::size_t> symbols;           // of node 2's decodes: it hears node 1's frames
  for (const auto& d : spy.decodes()) {
    if (d.node == 1) symbols.push_back(d.symbols);
  }
  ASSERT_FALSE(symbols.empty());
  for (const std::size_t n : symbols) EXPECT_GT(n, 100U);
}

}  // namespace
}  // namespace rfsitl::testing
