// Watching changes nothing: an observer that wants a receiver's samples (the
// dashboard, SigMF) gets them without running a receiver the engine would
// skip, and the noise is counter-based, so a run's deliveries, counters and
// even the samples themselves are the same whoever watches, and from when.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <vector>

#include "engine_run.hpp"
#include "rfsitl/engine/engine_observer.hpp"

namespace rfsitl::testing {
namespace {

using engine::LossReason;
using scenario::Scenario;

/// Wants node `node`'s samples in every tick from `from` on, and keeps them.
class WindowObserver final : public engine::EngineObserver {
 public:
  WindowObserver(std::size_t node, SampleTime from) : node_(node), from_(from) {}
  void on_frame_event(const engine::FrameEvent&) override {}
  bool wants_samples(std::size_t node, SampleTime tick_start, std::size_t) const override {
    return node == node_ && tick_start >= from_;
  }
  void on_rx_samples(std::size_t node, SampleTime time, std::span<const cf32> samples) override {
    if (node == node_) ticks[time].assign(samples.begin(), samples.end());
  }
  std::map<SampleTime, std::vector<cf32>> ticks;

 private:
  std::size_t node_;
  SampleTime from_;
};

/// Three nodes near the edge of decoding (noise `noise_db`), frames that
/// collide at node 2 and frames alone on the air, 60 ms.
Scenario marginal_triangle(double noise_db) {
  Scenario s = make_scenario(
      {{1, LocalPosition{0, 0, 0}}, {2, LocalPosition{5, 0, 0}}, {3, LocalPosition{0, 4, 1}}},
      0.06);
  s.channel.noise_variance = std::pow(10.0, noise_db / 10.0);
  s.traffic = {frame_at(0.002, 1, 2), frame_at(0.003, 3, 2, 40)};  // collide at node 2
  s.traffic.push_back(scenario::TrafficItem{0.010, 1, 2, 80, 12, 0.004});
  s.traffic.push_back(scenario::TrafficItem{0.012, 3, 1, 60, 10, 0.004});
  return s;
}

// At -50 dB the links sit at the edge of decoding: about two thirds of the
// frames arrive, and which ones is decided by the noise.
constexpr double kMarginalNoiseDb = -50.0;

std::uint64_t total(const RunResult& r, std::uint64_t engine::NodeCountersSnapshot::*field) {
  std::uint64_t sum = 0;
  for (const auto& c : r.counters) sum += c.*field;
  return sum;
}

TEST(EngineWatching, WatchingEveryReceiverChangesNoDeliveryOrCounter) {
  const Scenario s = marginal_triangle(kMarginalNoiseDb);
  const RunResult unwatched = run_engine(s);
  // The noise decides: some frames arrive, some do not.
  const std::uint64_t delivered = total(unwatched, &engine::NodeCountersSnapshot::delivered);
  std::uint64_t lost = 0;
  for (const auto& c : unwatched.counters) lost += c.lost_total();
  EXPECT_GT(delivered, 5U);
  EXPECT_GT(lost, 3U);

  WindowObserver w0(0, 0), w1(1, 0), w2(2, 0);
  const RunResult watched = run_engine(s, {.observers = {&w0, &w1, &w2}});
  expect_same_outcome(unwatched, watched);
  // The same receivers ran; the watched idle ticks were computed, not run.
  EXPECT_EQ(watched.status.receiver_ticks_run, unwatched.status.receiver_ticks_run);
  EXPECT_GT(watched.status.receiver_ticks_skipped, 0U);
  EXPECT_EQ(w1.ticks.size(), 60U);  // every tick of 1 ms in 60 ms
}

TEST(EngineWatching, SamplesAreTheSameWhenWatchedFromTheStartOrOnlyLate) {
  const Scenario s = marginal_triangle(kMarginalNoiseDb);
  constexpr SampleTime kLate = 30'000;  // 30 ms
  WindowObserver all(1, 0), late(1, kLate);
  run_engine(s, {.observers = {&all}});
  run_engine(s, {.observers = {&late}});
  ASSERT_EQ(late.ticks.size(), 30U);
  std::size_t with_signal = 0;
  for (const auto& [time, samples] : late.ticks) {
    ASSERT_TRUE(all.ticks.contains(time)) << time;
    EXPECT_EQ(all.ticks.at(time), samples) << "tick at " << time;
    double power = 0;
    for (const cf32 v : samples) power += std::norm(v);
    with_signal += power / static_cast<double>(samples.size()) > 3.0 ? 1U : 0U;  // noise: 1
  }
  // Both kinds of tick were compared: noise alone, and frames on the air.
  EXPECT_GT(with_signal, 0U);
  EXPECT_LT(with_signal, late.ticks.size());
}

TEST(EngineWatching, AtTheEdgeOfDecodingThreadCountAndSkippingChangeNothingEither) {
  Scenario s = marginal_triangle(kMarginalNoiseDb);
  const RunResult two = run_engine(s);
  s.engine.threads = 1;
  expect_same_outcome(two, run_engine(s));
  s.engine.threads = 2;
  s.engine.skip_idle_receivers = false;
  const RunResult no_skip = run_engine(s);
  expect_same_outcome(two, no_skip);
  EXPECT_GT(no_skip.status.receiver_ticks_run, two.status.receiver_ticks_run);
}

}  // namespace
}  // namespace rfsitl::testing
