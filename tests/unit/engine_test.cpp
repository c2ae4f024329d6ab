#include "rfsitl/engine/engine.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "rfsitl/registry/phy_registry.hpp"

namespace rfsitl::engine {
namespace {

using scenario::Scenario;
using scenario::TrafficItem;

struct Delivery {
  std::size_t node = 0;
  NetFrame frame;
  SampleTime tick_start = 0;  // virtual time of the tick in which it was delivered
  friend bool operator==(const Delivery&, const Delivery&) = default;
};

class Recorder final : public FrameSink {
 public:
  void deliver(std::size_t node, NetFrame&& frame) override {
    // status() is published after every tick: during a tick it names its start.
    deliveries.push_back({node, std::move(frame), engine->status().virtual_samples});
  }
  Engine* engine = nullptr;
  std::vector<Delivery> deliveries;
};

struct RunResult {
  std::vector<Delivery> deliveries;
  std::vector<NodeCountersSnapshot> counters;
  EngineStatus status;

  std::uint64_t lost(std::size_t node, LossReason r) const {
    return counters[node].lost[static_cast<std::size_t>(r)];
  }
};

using NodeSpec = std::pair<NodeId, std::optional<LocalPosition>>;

Scenario make_scenario(const std::vector<NodeSpec>& nodes, double duration_s) {
  Scenario s;
  s.name = "engine-test";
  s.seed = 7;
  for (const auto& [id, pos] : nodes) {
    scenario::NodeConfig n;
    n.id = id;
    if (pos) n.initial_position = Position{*pos};
    s.nodes.push_back(n);
  }
  s.channel.noise_variance = 1e-12;
  s.timing.mode = scenario::TimeMode::kVirtual;
  s.timing.sample_rate_hz = 1e6;
  s.timing.tick_samples = 1000;
  s.timing.duration_s = duration_s;
  s.engine.threads = 2;
  s.engine.stats_interval_s = 0.0;
  return s;
}

TrafficItem frame_at(double at_s, NodeId src, NodeId dst, std::size_t size = 80) {
  TrafficItem t;
  t.at_s = at_s;
  t.src = src;
  t.dst = dst;
  t.size_bytes = size;
  return t;
}

RunResult run(const Scenario& s, const std::function<void(Engine&)>& before = {}) {
  Recorder sink;
  auto engine = make_engine(s, sink);
  sink.engine = engine.get();
  if (before) before(*engine);
  const std::atomic<bool> stop{false};
  engine->run(stop);  // returns by itself once duration_s has been emulated
  RunResult r;
  r.deliveries = std::move(sink.deliveries);
  for (std::size_t i = 0; i < engine->num_nodes(); ++i) {
    r.counters.push_back(engine->counters(i).snapshot());
  }
  r.status = engine->status();
  return r;
}

std::vector<std::uint64_t> flat(const NodeCountersSnapshot& c) {
  std::vector<std::uint64_t> v{c.handed_in, c.queue_dropped, c.transmitted,
                               c.delivered, c.received,      c.rx_crc_failures};
  v.insert(v.end(), c.lost.begin(), c.lost.end());
  return v;
}

void expect_same_outcome(const RunResult& a, const RunResult& b) {
  EXPECT_EQ(a.deliveries, b.deliveries);
  ASSERT_EQ(a.counters.size(), b.counters.size());
  for (std::size_t i = 0; i < a.counters.size(); ++i) {
    EXPECT_EQ(flat(a.counters[i]), flat(b.counters[i])) << "node " << i;
  }
}

const std::vector<NodeSpec> kPair{{1, LocalPosition{0, 0, 0}}, {2, LocalPosition{5, 0, 0}}};
const std::vector<NodeSpec> kTriangle{
    {1, LocalPosition{0, 0, 0}}, {2, LocalPosition{5, 0, 0}}, {3, LocalPosition{0, 4, 1}}};

TEST(Engine, ScheduledFrameIsDeliveredToDestinationSinkWithItsContents) {
  Scenario s = make_scenario(kPair, 0.01);
  s.traffic.push_back(frame_at(0.002, 1, 2, 80));
  const RunResult r = run(s);
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

TEST(Engine, NonConsecutiveNodeIdsAreRoutedById) {
  Scenario s = make_scenario({{42, LocalPosition{0, 0, 0}}, {7, LocalPosition{3, 0, 0}}}, 0.01);
  s.traffic.push_back(frame_at(0.001, 7, 42, 16));
  const RunResult r = run(s);
  ASSERT_EQ(r.deliveries.size(), 1U);
  EXPECT_EQ(r.deliveries.front().node, 0U);  // id 42 is index 0
  EXPECT_EQ(r.deliveries.front().frame.src, 7);
  EXPECT_EQ(r.counters[1].delivered, 1U);
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
  const RunResult first = run(s);
  const RunResult second = run(s);
  EXPECT_GE(first.deliveries.size(), 5U);
  expect_same_outcome(first, second);
  s.engine.threads = 1;
  expect_same_outcome(first, run(s));
  s.engine.threads = 3;
  expect_same_outcome(first, run(s));
}

Scenario collision_free_schedule(std::size_t bytes) {
  Scenario s = make_scenario(kTriangle, 0.04);
  s.traffic = {frame_at(0.002, 1, 2, bytes), frame_at(0.008, 2, 3, bytes),
               frame_at(0.014, 3, 1, bytes), frame_at(0.020, 1, 255, bytes),
               frame_at(0.028, 2, 1, bytes)};
  return s;
}

TEST(Engine, SkippingIdleReceiversChangesNoDeliveryOrCounter) {
  for (std::size_t bytes : {10U, 80U}) {
    Scenario s = collision_free_schedule(bytes);
    s.engine.skip_idle_receivers = true;
    const RunResult on = run(s);
    s.engine.skip_idle_receivers = false;
    const RunResult off = run(s);
    EXPECT_EQ(on.deliveries.size(), 6U) << bytes << " bytes";  // broadcast reaches two
    expect_same_outcome(on, off);
    EXPECT_GT(on.status.receiver_ticks_skipped, 0U);
    EXPECT_LT(on.status.receiver_ticks_run, off.status.receiver_ticks_run);
    for (const RunResult* r : {&on, &off}) {
      EXPECT_EQ(r->status.receiver_ticks_run + r->status.receiver_ticks_skipped +
                    r->status.receiver_ticks_blanked,
                3U * 40U);
    }
  }
}

TEST(Engine, NoReceiverTickCountsAsSkippedWhenSkippingIsOff) {
  // 10-byte frames (778 samples) never blank a whole 1000-sample tick; 80-byte
  // frames (1898 samples) do, and a blanked transmitter's receiver is not "skipped as silent".
  for (std::size_t bytes : {10U, 80U}) {
    Scenario s = collision_free_schedule(bytes);
    s.engine.skip_idle_receivers = false;
    const RunResult off = run(s);
    EXPECT_EQ(off.status.receiver_ticks_skipped, 0U) << bytes << "-byte frames";
  }
}

TEST(Engine, NodesTransmittingToEachOtherAtOnceLoseBothToHalfDuplex) {
  Scenario s = make_scenario(kPair, 0.01);
  s.traffic = {frame_at(0.002, 1, 2), frame_at(0.002, 2, 1)};
  const RunResult r = run(s);
  EXPECT_TRUE(r.deliveries.empty());
  EXPECT_EQ(r.lost(0, LossReason::kHalfDuplex), 1U);
  EXPECT_EQ(r.lost(1, LossReason::kHalfDuplex), 1U);
}

TEST(Engine, EqualPowerSimultaneousFramesCollide) {
  Scenario s = make_scenario(
      {{1, LocalPosition{-5, 0, 0}}, {2, LocalPosition{0, 0, 0}}, {3, LocalPosition{5, 0, 0}}},
      0.01);
  s.traffic = {frame_at(0.002, 1, 2), frame_at(0.002, 3, 2)};
  const RunResult r = run(s);
  EXPECT_TRUE(r.deliveries.empty());
  EXPECT_EQ(r.lost(0, LossReason::kCollision), 1U);
  EXPECT_EQ(r.lost(2, LossReason::kCollision), 1U);
}

TEST(Engine, MuchStrongerFrameIsCapturedAndWeakerOneLostToCollision) {
  Scenario s = make_scenario(
      {{1, LocalPosition{-2, 0, 0}}, {2, LocalPosition{0, 0, 0}}, {3, LocalPosition{40, 0, 0}}},
      0.01);
  s.channel.noise_variance = 1e-12;  // -120 dB: node 3 alone would be at +23 dB SNR
  s.traffic = {frame_at(0.002, 1, 2), frame_at(0.002, 3, 2)};
  const RunResult r = run(s);
  ASSERT_EQ(r.deliveries.size(), 1U);
  EXPECT_EQ(r.deliveries.front().frame.src, 1);
  EXPECT_EQ(r.counters[0].delivered, 1U);
  EXPECT_EQ(r.counters[2].delivered, 0U);
  EXPECT_EQ(r.lost(2, LossReason::kCollision), 1U);
}

TEST(Engine, NodeWithoutPositionNeitherHearsNorIsHeard) {
  Scenario s =
      make_scenario({{1, LocalPosition{0, 0, 0}}, {2, LocalPosition{5, 0, 0}}, {3, {}}}, 0.02);
  s.traffic = {frame_at(0.001, 1, 3), frame_at(0.006, 3, 1), frame_at(0.012, 1, 2)};
  const RunResult r = run(s);
  ASSERT_EQ(r.deliveries.size(), 1U);
  EXPECT_EQ(r.deliveries.front().node, 1U);
  EXPECT_EQ(r.lost(0, LossReason::kBelowSensitivity), 1U);
  EXPECT_EQ(r.lost(2, LossReason::kBelowSensitivity), 1U);
  EXPECT_EQ(r.counters[2].received, 0U);
}

TEST(Engine, SharedNoiseSourceStillDelivers) {
  Scenario s = make_scenario(kTriangle, 0.015);
  s.channel.shared_noise = true;
  s.traffic = {frame_at(0.001, 1, 2), frame_at(0.006, 2, 255)};
  const RunResult r = run(s);
  EXPECT_EQ(r.deliveries.size(), 3U);
  EXPECT_EQ(r.counters[0].delivered, 1U);
  EXPECT_EQ(r.counters[1].delivered, 1U);
  EXPECT_EQ(r.counters[0].received + r.counters[2].received, 2U);
}

TEST(Engine, EveryHandedInFrameEndsDeliveredLostOrQueueDropped) {
  Scenario s = make_scenario({{1, LocalPosition{0, 0, 0}},
                              {2, LocalPosition{5, 0, 0}},
                              {3, LocalPosition{10, 0, 0}},
                              {4, LocalPosition{500, 0, 0}},
                              {5, {}}},
                             0.08);
  s.phy.tx_queue_frames = 2;
  s.traffic = {frame_at(0.001, 2, 1), frame_at(0.001, 3, 1), frame_at(0.004, 3, 255),
               frame_at(0.004, 4, 2), frame_at(0.010, 5, 1), frame_at(0.010, 2, 99),
               frame_at(0.015, 2, 3), frame_at(0.015, 3, 2), frame_at(0.020, 1, 255, 500)};
  s.traffic.push_back(TrafficItem{0.030, 3, 1, 30, 5, 0.0005});  // queue behind each other
  std::size_t submitted = 0;
  const RunResult r = run(s, [&](Engine& e) {
    for (int k = 0; k < 4; ++k) {
      e.submit(0, NetFrame{1, 3, std::vector<std::uint8_t>(20, 0xAB)});
      ++submitted;
    }
  });
  std::uint64_t handed_in = 0, delivered = 0, lost = 0, dropped = 0;
  for (std::size_t i = 0; i < r.counters.size(); ++i) {
    const NodeCountersSnapshot& c = r.counters[i];
    EXPECT_EQ(c.handed_in, c.delivered + c.lost_total() + c.queue_dropped) << "node " << i;
    EXPECT_EQ(c.transmitted, c.delivered + c.lost_total()) << "node " << i;
    EXPECT_EQ(c.pending(), 0U) << "node " << i;
    handed_in += c.handed_in;
    delivered += c.delivered;
    lost += c.lost_total();
    dropped += c.queue_dropped;
  }
  EXPECT_EQ(handed_in, submitted + 9U + 5U);
  EXPECT_EQ(dropped, 2U);  // queue of 2 frames
  EXPECT_GT(delivered, 0U);
  EXPECT_GT(lost, 0U);
  EXPECT_EQ(r.status.late_decodes, 0U);
}

}  // namespace
}  // namespace rfsitl::engine
