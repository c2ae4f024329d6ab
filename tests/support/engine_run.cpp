#include "engine_run.hpp"

#include <gtest/gtest.h>

#include <atomic>

namespace rfsitl::testing {

void RecordingSink::deliver(std::size_t node, NetFrame&& frame) {
  // status() is published after every tick: during a tick it names its start.
  deliveries.push_back({node, std::move(frame), engine->status().virtual_samples});
  if (on_deliver) on_deliver(*engine, deliveries.back());
}

RunResult run_engine(const scenario::Scenario& s, RunSetup setup) {
  RunResult r;
  r.sink = std::make_shared<RecordingSink>();
  r.sink->on_deliver = std::move(setup.on_deliver);
  r.engine = make_engine(s, *r.sink, std::move(setup.factory));
  r.sink->engine = r.engine.get();
  for (engine::EngineObserver* o : setup.observers) r.engine->add_observer(*o);
  if (setup.before) setup.before(*r.engine);
  const std::atomic<bool> stop{false};
  r.engine->run(stop);  // returns by itself once duration_s has been emulated
  r.deliveries = r.sink->deliveries;
  for (std::size_t i = 0; i < r.engine->num_nodes(); ++i) {
    r.counters.push_back(r.engine->counters(i).snapshot());
  }
  r.status = r.engine->status();
  return r;
}

scenario::Scenario make_scenario(const std::vector<NodeSpec>& nodes, double duration_s) {
  scenario::Scenario s;
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

scenario::TrafficItem frame_at(double at_s, NodeId src, NodeId dst, std::size_t size) {
  scenario::TrafficItem t;
  t.at_s = at_s;
  t.src = src;
  t.dst = dst;
  t.size_bytes = size;
  return t;
}

std::vector<scenario::TrafficItem> collision_free_traffic(std::size_t bytes) {
  return {frame_at(0.002, 1, 2, bytes), frame_at(0.008, 2, 3, bytes), frame_at(0.014, 3, 1, bytes),
          frame_at(0.020, 1, kBroadcastId, bytes), frame_at(0.028, 2, 1, bytes)};
}

namespace {

std::vector<std::uint64_t> flat(const engine::NodeCountersSnapshot& c) {
  std::vector<std::uint64_t> v{c.handed_in, c.queue_dropped, c.transmitted,
                               c.delivered, c.received,      c.rx_crc_failures};
  v.insert(v.end(), c.lost.begin(), c.lost.end());
  return v;
}

}  // namespace

void expect_same_outcome(const RunResult& a, const RunResult& b) {
  EXPECT_EQ(a.deliveries, b.deliveries);
  ASSERT_EQ(a.counters.size(), b.counters.size());
  for (std::size_t i = 0; i < a.counters.size(); ++i) {
    EXPECT_EQ(flat(a.counters[i]), flat(b.counters[i])) << "node " << i;
  }
}

}  // namespace rfsitl::testing
