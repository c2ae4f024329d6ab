// The engine with radios on their own frequencies: full-duplex (FDD) nodes
// send and receive at once, and a node retuned mid-run hears its new channel
// from the next tick, the retune told to observers (the pcap's comment).
#include <gtest/gtest.h>

#include <optional>
#include <vector>

#include "engine_run.hpp"
#include "rfsitl/engine/engine.hpp"
#include "scripted_position_source.hpp"

namespace rfsitl::testing {
namespace {

using engine::LossReason;

constexpr double kA = 2.400e9;
constexpr double kB = 2.405e9;  // 5 MHz from kA: out of a 1 MHz band with a flat mask

scenario::NodeTuning tuned(double tx_hz, double rx_hz, scenario::Duplex duplex) {
  scenario::NodeTuning t;
  t.tx_hz = tx_hz;
  t.rx_hz = rx_hz;
  t.duplex = duplex;
  return t;
}

/// Nodes 1 and 2, 5 m apart; 1 sends on kA and hears kB, 2 the other way
/// round; each sends `rounds` frames to the other, both at the same times.
scenario::Scenario fdd_pair(scenario::Duplex duplex, unsigned rounds) {
  scenario::Scenario s = make_scenario({{1, LocalPosition{0, 0, 0}}, {2, LocalPosition{5, 0, 0}}},
                                       0.01 * (rounds + 2));
  s.nodes[0].tuning = tuned(kA, kB, duplex);
  s.nodes[1].tuning = tuned(kB, kA, duplex);
  for (unsigned k = 0; k < rounds; ++k) {
    s.traffic.push_back(frame_at(0.01 * (k + 1), 1, 2));
    s.traffic.push_back(frame_at(0.01 * (k + 1), 2, 1));
  }
  return s;
}

TEST(EngineSpectrum, AnFddPairSendsAndReceivesAtOnce) {
  constexpr unsigned kRounds = 6;
  const RunResult r = run_engine(fdd_pair(scenario::Duplex::kFull, kRounds));
  for (std::size_t node = 0; node < 2; ++node) {
    EXPECT_EQ(r.counters[node].transmitted, kRounds) << node;
    EXPECT_EQ(r.counters[node].delivered, kRounds) << node;
    EXPECT_EQ(r.counters[node].received, kRounds) << node;
    EXPECT_EQ(r.lost(node, LossReason::kHalfDuplex), 0U) << node;
  }
}

TEST(EngineSpectrum, TheSamePairHalfDuplexLosesEveryFrameToItsOwnTransmitter) {
  // The control: the frequencies alone do not make a radio full duplex.
  constexpr unsigned kRounds = 6;
  const RunResult r = run_engine(fdd_pair(scenario::Duplex::kHalf, kRounds));
  for (std::size_t node = 0; node < 2; ++node) {
    EXPECT_EQ(r.counters[node].received, 0U) << node;
    EXPECT_EQ(r.lost(node, LossReason::kHalfDuplex), kRounds) << node;
  }
}

/// Records retunes.
class RetuneWatch final : public engine::EngineObserver {
 public:
  struct Seen {
    NodeId node;
    SampleTime time;
    double tx_hz;
    double rx_hz;
  };
  void on_frame_event(const engine::FrameEvent&) override {}
  void on_retune(NodeId node, SampleTime time, double tx_hz, double rx_hz) override {
    seen.push_back({node, time, tx_hz, rx_hz});
  }
  std::vector<Seen> seen;
};

TEST(EngineSpectrum, ARetunedNodeIsHeardOnItsNewChannelFromTheNextTick) {
  // Node 1 sends on kA every 10 ms; node 2 listens on kB until, in the tick
  // at 75 ms, it is retuned to kA: from the tick at 76 ms on it hears.
  scenario::Scenario s =
      make_scenario({{1, LocalPosition{0, 0, 0}}, {2, LocalPosition{5, 0, 0}}}, 0.12);
  s.nodes[0].tuning = tuned(kA, kA, scenario::Duplex::kHalf);
  s.nodes[1].tuning = tuned(kB, kB, scenario::Duplex::kHalf);
  std::vector<double> sent_at;
  for (int k = 1; k <= 7; ++k) sent_at.push_back(0.01 * k);  // 10 .. 70 ms: not heard
  sent_at.push_back(0.075);  // in the tick of the call: still not heard
  sent_at.push_back(0.076);  // the next tick: heard
  for (int k = 9; k <= 11; ++k) sent_at.push_back(0.01 * k);
  for (const double at : sent_at) s.traffic.push_back(frame_at(at, 1, 2));
  engine::Engine* engine = nullptr;
  bool done = false;
  TickHook hook(s.timing.sample_rate_hz, [&](double t_s) {
    if (!done && t_s >= 0.0745) {
      engine->retune(1, kA, kA);
      done = true;
    }
  });
  RetuneWatch watch;
  const RunResult r = run_engine(
      s, {.observers = {&hook, &watch}, .before = [&](engine::Engine& e) { engine = &e; }});
  ASSERT_TRUE(done);
  ASSERT_EQ(watch.seen.size(), 1U);
  EXPECT_EQ(watch.seen[0].node, 2U);
  EXPECT_EQ(watch.seen[0].time, 76'000);  // the tick after the call's
  EXPECT_EQ(watch.seen[0].tx_hz, kA);
  // Exactly the frames that started from the tick at 76 ms on.
  EXPECT_EQ(r.counters[1].received, 4U);
  EXPECT_EQ(r.counters[0].delivered, 4U);
  for (const Delivery& d : r.deliveries) EXPECT_GE(d.tick_start, 76'000) << d.frame.payload.size();
}

}  // namespace
}  // namespace rfsitl::testing
