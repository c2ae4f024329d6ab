// The engine's own logic on FakeTransceivers (tests/support): timing, routing,
// TX queues, losses and their reasons, skipping idle receivers, accounting.
// The fakes decide decodes from the samples the engine gives them, so these
// tests need no real PHY; every run also checks that the engine kept the
// Transceiver contract with each fake.
#include <gtest/gtest.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine_run.hpp"
#include "fake_fleet.hpp"
#include "spy_observer.hpp"

namespace rfsitl::testing {
namespace {

using engine::Engine;
using engine::LossReason;
using engine::NodeCountersSnapshot;
using scenario::Scenario;
using Kind = SpyObserver::Kind;

/// Frames of 100 + 8 n samples (80 bytes: 740, under one 1000-sample tick).
FakeConfig engine_fake_config(std::size_t rx_latency = 40) {
  FakeConfig c;
  c.rx_latency_samples = rx_latency;
  return c;
}

/// The payload the engine makes for a scenario frame (first repeat).
std::vector<std::uint8_t> scenario_payload(std::size_t size) {
  std::vector<std::uint8_t> p(size);
  for (std::size_t b = 0; b < size; ++b) p[b] = static_cast<std::uint8_t>(b & 0xFF);
  return p;
}

/// Runs `s` on `fleet`'s fakes; expects that each fake saw one begin_tick per
/// tick and no breach of the Transceiver contract.
RunResult run_on(FakeFleet& fleet, const Scenario& s, RunSetup setup = {}) {
  setup.factory = fleet.factory();
  RunResult r = run_engine(s, std::move(setup));
  const auto ticks = static_cast<std::uint64_t>(r.status.virtual_samples) / s.timing.tick_samples;
  for (std::size_t i = 0; i < fleet.size(); ++i) {
    EXPECT_EQ(fleet.radio(i).calls().contract_violations, 0U) << "node " << i;
    EXPECT_EQ(fleet.radio(i).calls().begin_tick, ticks) << "node " << i;
  }
  return r;
}

const std::vector<NodeSpec> kPair{{1, LocalPosition{0, 0, 0}}, {2, LocalPosition{5, 0, 0}}};
// Nodes 1 and 3 are equally far from node 2.
const std::vector<NodeSpec> kLine{
    {1, LocalPosition{-5, 0, 0}}, {2, LocalPosition{0, 0, 0}}, {3, LocalPosition{5, 0, 0}}};

TEST(EngineOnFakes, FrameGoesOnAirAtTheNextTickBoundaryAndIsDecodedFramePlusLatencyLater) {
  // 80 bytes from 2000: [2000, 2740). A latency of 260 makes the decode due
  // with the tick's last sample; 261, one sample into the next tick, where
  // nothing is on the air and only rx_busy() keeps the receiver running.
  for (const std::size_t latency : {260U, 261U}) {
    FakeFleet fleet(engine_fake_config(latency));
    SpyObserver spy;
    Scenario s = make_scenario(kPair, 0.006);
    s.traffic.push_back(frame_at(0.0015, 1, 2, 80));
    const RunResult r = run_on(fleet, s, {.observers = {&spy}});
    const auto tx = spy.events(Kind::kTransmitted);
    ASSERT_EQ(tx.size(), 1U);
    EXPECT_EQ(tx[0].time, 2000);
    EXPECT_EQ(tx[0].length_samples, 740U);
    ASSERT_EQ(fleet.radio(1).decodes().size(), 1U);
    EXPECT_EQ(fleet.radio(1).decodes()[0].reported_at, static_cast<SampleTime>(2740 + latency));
    ASSERT_EQ(r.deliveries.size(), 1U);
    EXPECT_EQ(r.deliveries[0].node, 1U);
    EXPECT_EQ(r.deliveries[0].frame, (NetFrame{1, 2, scenario_payload(80)}));
    EXPECT_EQ(r.deliveries[0].tick_start, latency == 260 ? 2000 : 3000);
    EXPECT_EQ(fleet.radio(1).calls().receive, latency == 260 ? 1U : 2U);
    EXPECT_EQ(r.counters[0].transmitted, 1U);
    EXPECT_EQ(r.counters[0].delivered, 1U);
    EXPECT_EQ(r.counters[1].received, 1U);
  }
}

TEST(EngineOnFakes, FrameSubmittedDuringATickGoesOnAirInTheNextTick) {
  // Node 2 answers node 1's frame from the sink, in the tick it is delivered.
  FakeFleet fleet(engine_fake_config());
  SpyObserver spy;
  Scenario s = make_scenario(kPair, 0.005);
  s.traffic.push_back(frame_at(0.001, 1, 2, 40));  // [1000, 1420), due at 1460
  bool answered = false;
  const auto answer = [&](Engine& e, const Delivery& d) {
    if (d.node != 1 || answered) return;
    answered = true;
    EXPECT_TRUE(e.submit(1, NetFrame{2, 1, {0xEE}}));
  };
  const RunResult r = run_on(fleet, s, {.observers = {&spy}, .on_deliver = answer});
  const auto handed = spy.events(Kind::kHandedIn);
  ASSERT_EQ(handed.size(), 2U);
  EXPECT_EQ(handed[1].node, 2);
  EXPECT_EQ(handed[1].time, 1000);
  const auto tx = spy.events(Kind::kTransmitted);
  ASSERT_EQ(tx.size(), 2U);
  EXPECT_EQ(tx[0].time, 1000);
  EXPECT_EQ(tx[1].time, 2000);
  ASSERT_EQ(r.deliveries.size(), 2U);
  EXPECT_EQ(r.deliveries[1].node, 0U);
  EXPECT_EQ(r.deliveries[1].frame, (NetFrame{2, 1, {0xEE}}));
  EXPECT_EQ(r.deliveries[1].tick_start, 2000);
}

TEST(EngineOnFakes, NonConsecutiveNodeIdsAreRoutedById) {
  FakeFleet fleet(engine_fake_config());
  Scenario s = make_scenario({{42, LocalPosition{0, 0, 0}}, {7, LocalPosition{3, 0, 0}}}, 0.005);
  s.traffic.push_back(frame_at(0.001, 7, 42, 16));
  const RunResult r = run_on(fleet, s);
  ASSERT_EQ(r.deliveries.size(), 1U);
  EXPECT_EQ(r.deliveries.front().node, 0U);  // id 42 is index 0
  EXPECT_EQ(r.deliveries.front().frame.src, 7);
  EXPECT_EQ(r.counters[1].delivered, 1U);
}

TEST(EngineOnFakes, BroadcastReachesEveryNodeInRangeAndIsDeliveredOnceOrLost) {
  FakeFleet fleet(engine_fake_config());
  SpyObserver spy;
  Scenario s = make_scenario({{1, LocalPosition{0, 0, 0}},
                              {2, LocalPosition{5, 0, 0}},
                              {3, LocalPosition{0, 4, 1}},
                              {4, LocalPosition{1000, 0, 0}}},  // -60 dB SNR from the others
                             0.008);
  s.traffic = {frame_at(0.002, 1, kBroadcastId), frame_at(0.004, 4, kBroadcastId)};
  const RunResult r = run_on(fleet, s, {.observers = {&spy}});
  ASSERT_EQ(r.deliveries.size(), 2U);
  EXPECT_EQ(r.deliveries[0].node, 1U);
  EXPECT_EQ(r.deliveries[1].node, 2U);
  EXPECT_EQ(r.counters[0].delivered, 1U);
  EXPECT_EQ(r.counters[1].received + r.counters[2].received + r.counters[3].received, 2U);
  EXPECT_EQ(r.counters[3].received, 0U);
  EXPECT_EQ(r.lost(3, LossReason::kBelowSensitivity), 1U);
  EXPECT_EQ(r.counters[3].delivered, 0U);
  // Delivered once, after both receptions (a broadcast waits for every verdict).
  const auto tx = spy.events(Kind::kTransmitted);
  ASSERT_EQ(tx.size(), 2U);
  std::vector<Kind> kinds;
  for (const auto& e : spy.of_serial(tx[0].serial)) kinds.push_back(e.kind);
  EXPECT_EQ(kinds, (std::vector<Kind>{Kind::kTransmitted, Kind::kReceived, Kind::kReceived,
                                      Kind::kDelivered}));
}

TEST(EngineOnFakes, FullTxQueueRefusesFramesAndTheQueuedOnesGoOutBackToBack) {
  FakeFleet fleet(engine_fake_config());
  SpyObserver spy;
  Scenario s = make_scenario(kPair, 0.005);
  s.phy.tx_queue_frames = 2;
  std::vector<bool> accepted;
  const auto submit_five = [&](Engine& e) {
    for (std::uint8_t k = 0; k < 5; ++k) accepted.push_back(e.submit(0, NetFrame{1, 2, {k, k}}));
    EXPECT_EQ(e.queue_depth(0), 2U);
  };
  const RunResult r = run_on(fleet, s, {.observers = {&spy}, .before = submit_five});
  EXPECT_EQ(accepted, (std::vector<bool>{true, true, false, false, false}));
  const NodeCountersSnapshot& c = r.counters[0];
  EXPECT_EQ(c.handed_in, 5U);
  EXPECT_EQ(c.queue_dropped, 3U);
  EXPECT_EQ(c.transmitted, 2U);
  EXPECT_EQ(c.delivered, 2U);
  EXPECT_EQ(c.pending(), 0U);
  const auto dropped = spy.events(Kind::kQueueDropped);
  ASSERT_EQ(dropped.size(), 3U);
  EXPECT_EQ(dropped[0].payload, (std::vector<std::uint8_t>{2, 2}));
  // 116-sample frames: the second starts at the first tick after the first ends.
  const auto tx = spy.events(Kind::kTransmitted);
  ASSERT_EQ(tx.size(), 2U);
  EXPECT_EQ(tx[0].time, 0);
  EXPECT_EQ(tx[1].time, 1000);
  ASSERT_EQ(r.deliveries.size(), 2U);
  EXPECT_EQ(r.deliveries[0].frame.payload, (std::vector<std::uint8_t>{0, 0}));
  EXPECT_EQ(r.deliveries[1].frame.payload, (std::vector<std::uint8_t>{1, 1}));
}

TEST(EngineOnFakes, NodesTransmittingToEachOtherAtOnceLoseBothToHalfDuplex) {
  FakeFleet fleet(engine_fake_config());
  Scenario s = make_scenario(kPair, 0.005);
  s.traffic = {frame_at(0.002, 1, 2), frame_at(0.002, 2, 1)};
  const RunResult r = run_on(fleet, s);
  EXPECT_TRUE(r.deliveries.empty());
  EXPECT_EQ(r.lost(0, LossReason::kHalfDuplex), 1U);
  EXPECT_EQ(r.lost(1, LossReason::kHalfDuplex), 1U);
  EXPECT_TRUE(fleet.radio(0).decodes().empty());
  EXPECT_TRUE(fleet.radio(1).decodes().empty());
}

TEST(EngineOnFakes, StartingToTransmitMidFrameResetsTheReceiverAndLosesTheFrame) {
  FakeFleet fleet(engine_fake_config());
  // Node 3 is 2 m from node 2 and 7 m from node 1: node 2's frame captures it.
  Scenario s = make_scenario(
      {{1, LocalPosition{0, 0, 0}}, {2, LocalPosition{5, 0, 0}}, {3, LocalPosition{7, 0, 0}}},
      0.007);
  s.traffic = {frame_at(0.002, 1, 2, 200),  // [2000, 3700)
               frame_at(0.003, 2, 3, 80)};  // [3000, 3740): node 2 stops listening
  const RunResult r = run_on(fleet, s);
  EXPECT_EQ(r.lost(0, LossReason::kHalfDuplex), 1U);
  EXPECT_EQ(r.counters[1].delivered, 1U);
  EXPECT_EQ(fleet.radio(1).calls().reset_receiver, 1U);
  EXPECT_TRUE(fleet.radio(1).decodes().empty());
  ASSERT_EQ(r.deliveries.size(), 1U);
  EXPECT_EQ(r.deliveries[0].node, 2U);
}

TEST(EngineOnFakes, EqualPowerSimultaneousFramesCollide) {
  FakeFleet fleet(engine_fake_config());
  Scenario s = make_scenario(kLine, 0.005);
  s.traffic = {frame_at(0.002, 1, 2), frame_at(0.002, 3, 2)};
  const RunResult r = run_on(fleet, s);
  EXPECT_TRUE(r.deliveries.empty());
  EXPECT_EQ(r.lost(0, LossReason::kCollision), 1U);
  EXPECT_EQ(r.lost(2, LossReason::kCollision), 1U);
  EXPECT_EQ(r.counters[1].rx_crc_failures, 0U);  // neither header survived
}

TEST(EngineOnFakes, FrameHitInItsPayloadIsACrcFailureAtTheReceiverAndACollision) {
  FakeFleet fleet(engine_fake_config());
  Scenario s = make_scenario(kLine, 0.007);
  s.traffic = {frame_at(0.002, 1, 2, 200),  // [2000, 3700), payload from 2100
               frame_at(0.003, 3, 2, 80)};  // [3000, 3740)
  const RunResult r = run_on(fleet, s);
  EXPECT_TRUE(r.deliveries.empty());
  EXPECT_EQ(r.counters[1].rx_crc_failures, 1U);
  EXPECT_EQ(r.counters[1].received, 0U);
  EXPECT_EQ(r.lost(0, LossReason::kCollision), 1U);
  EXPECT_EQ(r.lost(2, LossReason::kCollision), 1U);
}

TEST(EngineOnFakes, LossReasonComesFromTheSensitivityTheSenderStatesNotFromTheReceiver) {
  // 45 m at -120 dB noise: about 20 dB SNR. The receiver decodes it when it
  // needs 10 dB, not 30; the engine names a loss from what the sender's
  // transceiver states, so a 10 dB claim leaves nothing to blame but decoding.
  struct Case {
    double receiver_needs_db;
    double sender_claims_db;
    std::optional<LossReason> reason;  // nullopt: delivered
  };
  for (const Case& k : {Case{10, 10, std::nullopt}, Case{30, 30, LossReason::kBelowSensitivity},
                        Case{30, 10, LossReason::kDecodeFailure}}) {
    FakeFleet fleet(engine_fake_config());
    fleet.config(0).claimed_sensitivity_snr_db = k.sender_claims_db;
    fleet.config(1).sensitivity_snr_db = k.receiver_needs_db;
    Scenario s = make_scenario({{1, LocalPosition{0, 0, 0}}, {2, LocalPosition{45, 0, 0}}}, 0.005);
    s.traffic = {frame_at(0.001, 1, 2)};
    const RunResult r = run_on(fleet, s);
    const auto label = [&] {
      return std::to_string(k.receiver_needs_db) + "/" + std::to_string(k.sender_claims_db);
    };
    EXPECT_EQ(r.counters[0].delivered, k.reason ? 0U : 1U) << label();
    if (k.reason) {
      EXPECT_EQ(r.lost(0, *k.reason), 1U) << label();
    }
  }
}

TEST(EngineOnFakes, NodeWithoutPositionNeitherHearsNorIsHeardAndIsNeverRunWhileSilent) {
  FakeFleet fleet(engine_fake_config());
  Scenario s =
      make_scenario({{1, LocalPosition{0, 0, 0}}, {2, LocalPosition{5, 0, 0}}, {3, {}}}, 0.01);
  s.traffic = {frame_at(0.001, 1, 3), frame_at(0.004, 3, 1), frame_at(0.007, 1, 2)};
  const RunResult r = run_on(fleet, s);
  ASSERT_EQ(r.deliveries.size(), 1U);
  EXPECT_EQ(r.deliveries.front().node, 1U);
  EXPECT_EQ(r.lost(0, LossReason::kBelowSensitivity), 1U);
  EXPECT_EQ(r.lost(2, LossReason::kBelowSensitivity), 1U);
  EXPECT_EQ(r.counters[2].received, 0U);
  // Node 3 runs its receiver only after its own transmission (the T/R switch
  // resets it); node 1 never hears it, so it does not run for node 3's frame.
  EXPECT_EQ(fleet.radio(2).calls().receive, 1U);
  EXPECT_EQ(fleet.radio(2).calls().reset_receiver, 1U);
  EXPECT_EQ(fleet.radio(0).calls().receive, 2U);  // after each of its own two frames
}

Scenario collision_free_schedule(std::size_t bytes) {
  Scenario s = make_scenario({{1, LocalPosition{0, 0, 0}},
                              {2, LocalPosition{5, 0, 0}},
                              {3, LocalPosition{0, 4, 1}},
                              {4, {}}},  // no position: hears nothing
                             0.04);
  s.traffic = collision_free_traffic(bytes);
  return s;
}

TEST(EngineOnFakes, SkippingIdleReceiversRunsExactlyThoseThatHearSomethingAndChangesNoOutcome) {
  // 10 bytes: 180 samples, inside one tick. 200 bytes: 1700 samples, a wholly
  // blanked tick for the sender, then a tick everybody hears.
  for (const std::size_t bytes : {10U, 200U}) {
    Scenario s = collision_free_schedule(bytes);
    FakeFleet on_fleet(engine_fake_config());
    FakeFleet off_fleet(engine_fake_config());
    s.engine.skip_idle_receivers = true;
    const RunResult on = run_on(on_fleet, s);
    s.engine.skip_idle_receivers = false;
    const RunResult off = run_on(off_fleet, s);
    EXPECT_EQ(on.deliveries.size(), 6U) << bytes;  // the broadcast reaches two
    expect_same_outcome(on, off);
    // Per frame, the two other positioned receivers in each tick it is on the
    // air, and the sender's in the tick its transmission ends.
    EXPECT_EQ(on.status.receiver_ticks_run, bytes == 10 ? 5U * 3U : 5U * 5U) << bytes;
    EXPECT_EQ(on.status.receiver_ticks_blanked, bytes == 10 ? 0U : 5U) << bytes;
    EXPECT_EQ(off.status.receiver_ticks_skipped, 0U) << bytes;
    for (const auto& [r, fleet] : {std::pair{&on, &on_fleet}, std::pair{&off, &off_fleet}}) {
      EXPECT_EQ(r->status.receiver_ticks_run + r->status.receiver_ticks_skipped +
                    r->status.receiver_ticks_blanked,
                4U * 40U);
      // The engine's count is what the transceivers saw.
      EXPECT_EQ(fleet->total(&FakeCalls::receive), r->status.receiver_ticks_run) << bytes;
    }
    EXPECT_EQ(on_fleet.radio(3).calls().receive, 0U);
    EXPECT_EQ(off_fleet.radio(3).calls().receive, 40U);
  }
}

/// Checks every tick that no node's counters show more outcomes than frames.
class CounterWatch final : public engine::EngineObserver {
 public:
  void on_frame_event(const engine::FrameEvent&) override {}
  bool wants_samples(std::size_t node, SampleTime, std::size_t) const override {
    return node == 0;  // a call every tick
  }
  void on_rx_samples(std::size_t, SampleTime, std::span<const cf32>) override {
    ++ticks;
    for (std::size_t i = 0; i < engine->num_nodes(); ++i) {
      const NodeCountersSnapshot c = engine->counters(i).snapshot();
      const std::uint64_t outcomes = c.delivered + c.lost_total();
      if (c.handed_in < c.queue_dropped + outcomes || c.transmitted < outcomes) ++breaches;
    }
  }
  Engine* engine = nullptr;
  std::uint64_t ticks = 0;
  std::uint64_t breaches = 0;
};

TEST(EngineOnFakes, EveryHandedInFrameEndsDeliveredLostOrQueueDroppedExactlyOnce) {
  FakeFleet fleet(engine_fake_config());
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
  s.traffic.push_back(scenario::TrafficItem{0.030, 3, 1, 30, 5, 0.0005});  // queue up
  CounterWatch watch;
  const auto submit_four = [&](Engine& e) {
    watch.engine = &e;
    for (int k = 0; k < 4; ++k) e.submit(0, NetFrame{1, 3, std::vector<std::uint8_t>(20, 0xAB)});
  };
  const RunResult r = run_on(fleet, s, {.observers = {&watch}, .before = submit_four});
  EXPECT_EQ(watch.ticks, 80U);
  EXPECT_EQ(watch.breaches, 0U);  // pending never went negative, at any tick
  std::uint64_t handed_in = 0, delivered = 0, transmitted = 0, dropped = 0;
  for (std::size_t i = 0; i < r.counters.size(); ++i) {
    const NodeCountersSnapshot& c = r.counters[i];
    EXPECT_EQ(c.handed_in, c.delivered + c.lost_total() + c.queue_dropped) << "node " << i;
    EXPECT_EQ(c.transmitted, c.delivered + c.lost_total()) << "node " << i;
    EXPECT_EQ(c.pending(), 0U) << "node " << i;
    handed_in += c.handed_in;
    delivered += c.delivered;
    transmitted += c.transmitted;
    dropped += c.queue_dropped;
  }
  EXPECT_EQ(handed_in, 4U + 9U + 5U);
  EXPECT_EQ(dropped, 2U);  // queue of 2 frames
  EXPECT_EQ(transmitted, fleet.total(&FakeCalls::start_frame));
  EXPECT_GT(delivered, 0U);
  EXPECT_EQ(r.lost(1, LossReason::kUnknownDestination), 1U);  // to 99
  EXPECT_EQ(r.lost(3, LossReason::kBelowSensitivity), 1U);    // 500 m: -42 dB
  EXPECT_EQ(r.lost(4, LossReason::kBelowSensitivity), 1U);    // no position
  EXPECT_EQ(r.status.late_decodes, 0U);
}

}  // namespace
}  // namespace rfsitl::testing
