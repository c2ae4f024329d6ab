// The engine's observer interface: the frame events agree with the counters,
// a watched node's samples arrive every tick, and decodes carry constellations.
#include <gtest/gtest.h>

#include <atomic>
#include <map>
#include <mutex>
#include <set>
#include <vector>

#include "rfsitl/engine/engine.hpp"

namespace rfsitl::engine {
namespace {

class NullSink final : public FrameSink {
 public:
  void deliver(std::size_t, NetFrame&&) override {}
};

class Collector final : public EngineObserver {
 public:
  explicit Collector(std::optional<std::size_t> watch = std::nullopt) : watch_(watch) {}
  void on_frame_event(const FrameEvent& e) override {
    std::lock_guard lock(mutex);
    events.push_back(e);
  }
  bool wants_samples(std::size_t node, SampleTime, std::size_t) const override {
    return watch_ == node;
  }
  void on_rx_samples(std::size_t, SampleTime t, std::span<const cf32> s) override {
    tick_times.push_back(t);
    double p = 0;
    for (const cf32 v : s) p += std::norm(v);
    tick_power.push_back(p / static_cast<double>(s.size()));
    sizes.insert(s.size());
  }
  void on_decode(std::size_t node, SampleTime, const phy::RxEvent& ev) override {
    std::lock_guard lock(mutex);
    decode_symbols[node].push_back(ev.symbols.size());
  }
  std::mutex mutex;
  std::vector<FrameEvent> events;
  std::vector<SampleTime> tick_times;
  std::vector<double> tick_power;
  std::set<std::size_t> sizes;
  std::map<std::size_t, std::vector<std::size_t>> decode_symbols;

 private:
  std::optional<std::size_t> watch_;
};

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

/// Runs `s` to its end with `c` observing; returns the engine for its counters.
std::unique_ptr<Engine> run_observed(const scenario::Scenario& s, Collector& c) {
  static NullSink sink;
  auto engine = make_engine(s, sink);
  engine->add_observer(c);
  const std::atomic<bool> stop{false};
  engine->run(stop);
  return engine;
}

TEST(EngineObserver, FrameEventsAgreeWithEveryNodesCounters) {
  Collector c;
  const auto engine = run_observed(busy_scenario(), c);
  std::map<std::pair<NodeId, FrameEventKind>, std::uint64_t> kinds;
  const auto count = [&](NodeId id, FrameEventKind k) { return kinds[std::make_pair(id, k)]; };
  std::map<std::pair<NodeId, LossReason>, std::uint64_t> reasons;
  std::map<std::uint32_t, std::vector<FrameEventKind>> by_serial;
  for (const FrameEvent& e : c.events) {
    ++kinds[{e.node, e.kind}];
    if (e.kind == FrameEventKind::kLost) ++reasons[{e.node, *e.reason}];
    if (e.kind != FrameEventKind::kHandedIn) by_serial[e.serial].push_back(e.kind);
  }
  std::uint64_t losses = 0;
  for (std::size_t i = 0; i < engine->num_nodes(); ++i) {
    const auto k = engine->counters(i).snapshot();
    const NodeId id = engine->node_ids()[i];
    EXPECT_EQ(count(id, FrameEventKind::kHandedIn), k.handed_in) << int{id};
    EXPECT_EQ(count(id, FrameEventKind::kTransmitted), k.transmitted) << int{id};
    EXPECT_EQ(count(id, FrameEventKind::kDelivered), k.delivered) << int{id};
    EXPECT_EQ(count(id, FrameEventKind::kReceived), k.received) << int{id};
    for (std::size_t r = 0; r < kNumLossReasons; ++r) {
      EXPECT_EQ(reasons[std::make_pair(id, static_cast<LossReason>(r))], k.lost[r])
          << int{id} << " " << r;
    }
    losses += k.lost_total();
  }
  EXPECT_GT(losses, 0U);  // the scenario exercises losses as well as deliveries
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

TEST(EngineObserver, WatchedNodeGetsEveryTicksSamplesNoiseAtUnitPowerAndZerosWhileItSends) {
  scenario::Scenario s = busy_scenario();
  s.timing.duration_s = 0.2;
  Collector c(0);  // node 1, which also transmits
  run_observed(s, c);
  const std::size_t ticks = static_cast<std::size_t>(0.2 * 1e6 / s.timing.tick_samples);
  ASSERT_EQ(c.tick_times.size(), ticks);
  for (std::size_t k = 0; k < ticks; ++k) {
    ASSERT_EQ(c.tick_times[k], static_cast<SampleTime>(k * s.timing.tick_samples));
  }
  EXPECT_EQ(c.sizes, std::set<std::size_t>{s.timing.tick_samples});
  // Before any traffic (10 ms): pure noise at the front-end scale.
  double early = 0;
  for (std::size_t k = 0; k < 30; ++k) early += c.tick_power[k];
  EXPECT_NEAR(early / 30, 1.0, 0.05);
  // While node 1 sends a whole tick its receiver is blanked: exactly zero.
  EXPECT_TRUE(
      std::any_of(c.tick_power.begin(), c.tick_power.end(), [](double p) { return p == 0.0; }));
  // And while others send to it, far above the noise.
  EXPECT_TRUE(
      std::any_of(c.tick_power.begin(), c.tick_power.end(), [](double p) { return p > 100.0; }));
}

TEST(EngineObserver, DecodesCarryTheirConstellation) {
  Collector c;
  run_observed(busy_scenario(), c);
  ASSERT_FALSE(c.decode_symbols[1].empty());  // node 2 hears node 1's frames
  for (const std::size_t n : c.decode_symbols[1]) EXPECT_GT(n, 100U);
}

}  // namespace
}  // namespace rfsitl::engine
