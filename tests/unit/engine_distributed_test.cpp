// A distributed run (K ranks, here threads with ThreadPeerGroup instead of
// MPI processes) gives every node the counters and deliveries of one process:
// traffic with collisions, moving nodes, a MAC with acknowledgements and
// retries, and nodes moved from outside during the run.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <thread>

#include "engine_run.hpp"
#include "rfsitl/cluster/node_assignment.hpp"
#include "rfsitl/common/geodesy.hpp"
#include "rfsitl/monitor/live_view.hpp"
#include "rfsitl/position/mobility/mobility_component.hpp"
#include "rfsitl/registry/mac_registry.hpp"
#include "rfsitl/registry/mobility_registry.hpp"
#include "thread_peers.hpp"

namespace rfsitl::testing {
namespace {

/// Six nodes, two of them on orbits through the others' range, every node
/// sending to the next at the same instants (collisions), a broadcast, and
/// frames to a node out of range; csma or none.
scenario::Scenario busy_swarm(const std::string& mac) {
  scenario::Scenario s = make_scenario({{1, LocalPosition{0, 0, 10}},
                                        {2, LocalPosition{20, 0, 10}},
                                        {3, LocalPosition{40, 0, 10}},
                                        {4, std::nullopt},
                                        {5, LocalPosition{20, 30, 10}},
                                        {6, std::nullopt}},
                                       1.2);
  s.engine.mobility_update_s = 0.01;
  const auto* orbit = position::mobility::find_mobility("orbit");
  for (const std::size_t i : {std::size_t{3}, std::size_t{5}}) {
    scenario::MobilityChoice m{"orbit", orbit->info.defaults()};
    m.settings.set("centre_x_m", 20.0 * static_cast<double>(i - 2));
    m.settings.set("radius_m", 50.0);
    m.settings.set("speed_mps", 40.0);
    s.nodes[i].mobility = m;
  }
  s.mac.type = mac;
  s.mac.settings = mac::find_mac(mac)->info.defaults();
  // Intervals that differ by sender: frames overlap in ever other ways.
  for (NodeId src = 1; src <= 6; ++src) {
    scenario::TrafficItem t = frame_at(0.01 + 0.003 * src, src, src % 6 + 1, 60);
    t.repeat = 40;
    t.interval_s = 0.011 + 0.0023 * src;
    s.traffic.push_back(t);
  }
  scenario::TrafficItem b = frame_at(0.033, 2, kBroadcastId, 40);
  b.repeat = 10;
  b.interval_s = 0.1;
  s.traffic.push_back(b);
  return s;
}

struct RankRun {
  std::vector<engine::NodeCountersSnapshot> counters;  // every node, after the final merge
  std::vector<Delivery> deliveries;                    // this rank's nodes'
  engine::EngineStatus status;
  std::vector<engine::RankStatus> ranks;
};

/// Runs `s` on `k` ranks (threads); `before(rank, engine)` runs before each.
std::vector<RankRun> run_ranks(
    const scenario::Scenario& s, std::size_t k,
    const std::function<void(std::size_t, engine::Engine&)>& before = {}) {
  ThreadPeerGroup group(k);
  const std::vector<std::size_t> owner = cluster::assign_nodes(s, k);
  std::vector<RankRun> out(k);
  std::vector<std::thread> threads;
  for (std::size_t r = 0; r < k; ++r) {
    threads.emplace_back([&, r] {
      RecordingSink sink;
      auto e = engine::make_engine(s, sink, {}, engine::Distribution{&group.peer(r), owner, 1});
      sink.engine = e.get();
      if (before) before(r, *e);
      const std::atomic<bool> stop{false};
      e->run(stop);
      for (std::size_t i = 0; i < e->num_nodes(); ++i) {
        out[r].counters.push_back(e->counters(i).snapshot());
      }
      out[r].deliveries = sink.deliveries;
      out[r].status = e->status();
      out[r].ranks = e->ranks();
    });
  }
  for (auto& t : threads) t.join();
  return out;
}

std::vector<Delivery> sorted(std::vector<Delivery> d) {
  std::stable_sort(d.begin(), d.end(), [](const Delivery& a, const Delivery& b) {
    return std::tie(a.tick_start, a.node) < std::tie(b.tick_start, b.node);
  });
  return d;
}

void expect_same_as_one_process(const RunResult& one, const std::vector<RankRun>& ranks) {
  std::vector<Delivery> all;
  for (std::size_t r = 0; r < ranks.size(); ++r) {
    SCOPED_TRACE("rank " + std::to_string(r) + " of " + std::to_string(ranks.size()));
    ASSERT_EQ(ranks[r].counters.size(), one.counters.size());
    for (std::size_t i = 0; i < one.counters.size(); ++i) {
      SCOPED_TRACE("node index " + std::to_string(i));
      const auto& a = one.counters[i];
      const auto& b = ranks[r].counters[i];
      EXPECT_EQ(b.handed_in, a.handed_in);
      EXPECT_EQ(b.transmitted, a.transmitted);
      EXPECT_EQ(b.delivered, a.delivered);
      EXPECT_EQ(b.lost, a.lost);
      EXPECT_EQ(b.received, a.received);
      EXPECT_EQ(b.rx_crc_failures, a.rx_crc_failures);
      EXPECT_EQ(b.mac.retries, a.mac.retries);
      EXPECT_EQ(b.mac.control_sent, a.mac.control_sent);
      EXPECT_EQ(b.mac.busy_ticks, a.mac.busy_ticks);
      EXPECT_EQ(b.mac.backoff_slots, a.mac.backoff_slots);
    }
    EXPECT_EQ(ranks[r].ranks.size(), ranks.size());
    EXPECT_EQ(ranks[r].status.virtual_samples, one.status.virtual_samples);
    all.insert(all.end(), ranks[r].deliveries.begin(), ranks[r].deliveries.end());
  }
  // Deliveries: the same frames to the same nodes in the same ticks.
  const std::vector<Delivery> got = sorted(all), want = sorted(one.deliveries);
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t k = 0; k < got.size(); ++k) {
    EXPECT_TRUE(got[k] == want[k])
        << "delivery " << k << ": node " << got[k].node << " at " << got[k].tick_start
        << " against node " << want[k].node << " at " << want[k].tick_start;
  }
}

TEST(EngineDistributed, RanksGiveTheCountersOfOneProcess) {
  const scenario::Scenario s = busy_swarm("none");
  const RunResult one = run_engine(s);
  // The scenario exercises what the exchange must carry: collisions, frames
  // lost to distance as nodes move, deliveries, broadcasts.
  std::uint64_t delivered = 0, collided = 0, received = 0;
  for (const auto& c : one.counters) {
    delivered += c.delivered;
    collided += c.lost[static_cast<std::size_t>(engine::LossReason::kCollision)];
    received += c.received;
  }
  EXPECT_GT(delivered, 10U);
  EXPECT_GT(collided, 5U);
  EXPECT_GT(received, delivered);  // broadcasts reach several
  for (const std::size_t k : {1U, 2U, 3U}) expect_same_as_one_process(one, run_ranks(s, k));
}

TEST(EngineDistributed, RankZerosLiveViewShowsTheLinksOfEveryRankAsOneProcessWould) {
  // The dashboard's link outcomes: a live view on every rank, which share
  // what they saw; rank 0's then holds what one process's does.
  const scenario::Scenario s = busy_swarm("none");
  std::vector<NodeId> ids;
  for (const auto& n : s.nodes) ids.push_back(n.id);
  monitor::LiveView alone(ids);
  RunSetup setup;
  setup.observers = {&alone};
  run_engine(s, setup);
  const auto want = alone.link_outcomes();
  std::uint32_t links_seen = 0;
  for (std::size_t k = 0; k < want.received.size(); ++k) {
    links_seen += (want.received[k] > 0 ? 1 : 0) + (want.lost[k] > 0 ? 1 : 0);
  }
  EXPECT_GT(links_seen, 6U);
  for (const std::size_t k : {2U, 3U}) {
    SCOPED_TRACE(std::to_string(k) + " ranks");
    std::vector<std::unique_ptr<monitor::LiveView>> views;
    for (std::size_t r = 0; r < k; ++r) views.push_back(std::make_unique<monitor::LiveView>(ids));
    run_ranks(s, k, [&](std::size_t r, engine::Engine& e) { e.add_observer(*views[r]); });
    const auto got = views[0]->link_outcomes();
    EXPECT_EQ(got.received, want.received);
    EXPECT_EQ(got.lost, want.lost);
    EXPECT_EQ(views[0]->bad_shares(), 0U);
  }
}

TEST(EngineDistributed, RanksGiveTheCountersOfOneProcessWithCsma) {
  const scenario::Scenario s = busy_swarm("csma");
  const RunResult one = run_engine(s);
  std::uint64_t retries = 0, acks = 0;
  for (const auto& c : one.counters) {
    retries += c.mac.retries;
    acks += c.mac.control_sent;
  }
  EXPECT_GT(acks, 10U);
  EXPECT_GT(retries, 0U);
  expect_same_as_one_process(one, run_ranks(s, 2));
  expect_same_as_one_process(one, run_ranks(s, 4));
}

TEST(EngineDistributed, AMoveReportedToOneRankMovesTheNodeOnEveryRank) {
  scenario::Scenario s = busy_swarm("none");
  s.timing.duration_s = 0.3;
  // Node 6 (index 5) starts far; rank 0 is told it is at the origin before
  // the run (a location port's report). Every rank must see it there.
  s.nodes[5].mobility.reset();
  s.nodes[5].initial_position = Position{LocalPosition{5000, 0, 10}};
  const Ecef near = to_ecef(Position{LocalPosition{1, 1, 10}}, s.channel.origin);
  const auto ranks = run_ranks(s, 2, [&](std::size_t r, engine::Engine& e) {
    if (r == 0) e.set_position(5, near);
  });
  // The frames to node 6 (from node 5) arrive only if every rank moved it:
  // its receiver runs on its owner, the sender's rank decides nothing.
  const RunResult moved =
      run_engine(s, RunSetup{{}, {}, [&](engine::Engine& e) { e.set_position(5, near); }});
  EXPECT_GT(moved.counters[4].delivered, 0U);
  std::uint64_t delivered_5 = 0;
  for (const RankRun& r : ranks) delivered_5 = std::max(delivered_5, r.counters[4].delivered);
  EXPECT_EQ(delivered_5, moved.counters[4].delivered);
}

TEST(EngineDistributed, RanksStopTogetherWhenOneIsTold) {
  scenario::Scenario s = busy_swarm("none");
  s.timing.duration_s = 0;  // until stopped
  ThreadPeerGroup group(2);
  const std::vector<std::size_t> owner = cluster::assign_nodes(s, 2);
  std::atomic<bool> stop0{false};
  const std::atomic<bool> never{false};
  std::vector<SampleTime> ended(2);
  std::vector<std::thread> threads;
  for (std::size_t r = 0; r < 2; ++r) {
    threads.emplace_back([&, r] {
      RecordingSink sink;
      auto e = engine::make_engine(s, sink, {}, engine::Distribution{&group.peer(r), owner, 1});
      sink.engine = e.get();
      e->run(r == 0 ? stop0 : never);
      ended[r] = e->status().virtual_samples;
    });
  }
  while (group.exchanges() < 200) std::this_thread::yield();
  stop0.store(true);
  for (auto& t : threads) t.join();
  EXPECT_GT(ended[0], 0);
  EXPECT_EQ(ended[0], ended[1]);
}

}  // namespace
}  // namespace rfsitl::testing
