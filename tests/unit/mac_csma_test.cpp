// The MAC "csma" alone: a fake queue, a fake air time, and carrier sense and
// decodes played by the test, tick by tick.
#include <gtest/gtest.h>

#include <memory>
#include <set>
#include <vector>

#include "fake_frame_queue.hpp"
#include "rfsitl/registry/mac_registry.hpp"

namespace rfsitl::mac {
namespace {

constexpr std::size_t kTick = 100;

using FakeQueue = testing::FakeFrameQueue;

/// One node's csma MAC, its counters and its queue; time advances a tick per step.
struct Station {
  explicit Station(config::Settings settings = find_mac("csma")->info.defaults(), NodeId id = 1,
                   std::uint64_t seed = 0) {
    MacContext c;
    c.id = id;
    c.sample_rate_hz = 1e6;
    c.tick_samples = kTick;
    c.radio_max_payload = 2048;
    c.frame_samples = [](std::size_t bytes) { return 200 + 10 * bytes; };
    c.rx_latency_samples = 20;
    c.seed = seed * 1000 + 7 + id;
    c.counters = &counters;
    mac = find_mac("csma")->make(settings, c);
  }

  /// One tick: the MAC decides, the transmission (if any) lasts its air time,
  /// then carrier sense reports `busy` (or the node's own transmission).
  std::optional<MacTransmission> step(bool busy = false) {
    auto send = decide();
    sense(busy);
    return send;
  }

  /// The first half of a tick: the MAC decides, and a transmission starts.
  std::optional<MacTransmission> decide() {
    const bool tx_busy = now < tx_end;
    auto send = mac->on_tick(now, tx_busy, queue);
    if (send) {
      const std::size_t len =
          200 + 10 * (1 + send->header.size() +
                      (send->frame != nullptr ? send->frame->payload.size() : 0));
      tx_end = now + static_cast<SampleTime>(len);
      mac->on_sent(now, tx_end);
      // The header is the MAC's buffer, valid until its next call: copied.
      sent.push_back({*send, {send->header.begin(), send->header.end()}, now});
    }
    verdicts.push_back(mac->take_verdict());
    return send;
  }

  /// The second half: carrier sense over the tick, and time moves on.
  void sense(bool busy) {
    mac->on_sensed(busy || now < tx_end);
    now += kTick;
  }

  /// Transmitting during the current tick.
  bool on_air() const { return now < tx_end; }

  /// Steps until the MAC sends (at most `limit` ticks); nullopt if it never does.
  std::optional<MacTransmission> step_until_send(std::size_t limit, bool busy = false) {
    for (std::size_t i = 0; i < limit; ++i) {
      if (auto s = step(busy)) return s;
    }
    return std::nullopt;
  }

  std::optional<Verdict> last_verdict() const {
    for (auto it = verdicts.rbegin(); it != verdicts.rend(); ++it) {
      if (*it) return *it;
    }
    return std::nullopt;
  }

  MacCounters counters;
  FakeQueue queue;
  std::unique_ptr<Mac> mac;
  SampleTime now = 0;
  SampleTime tx_end = 0;
  struct Sent {
    MacTransmission t;
    std::vector<std::uint8_t> header;
    SampleTime at;
  };
  std::vector<Sent> sent;
  std::vector<std::optional<Verdict>> verdicts;
};

config::Settings csma_with(std::string_view key, config::Value v) {
  config::Settings s = find_mac("csma")->info.defaults();
  s.set(key, std::move(v));
  return s;
}

// Defaults at these ticks: slot 250 us = 3 ticks, SIFS 3 ticks, DIFS 9 ticks,
// backoffs of a first attempt 0..15 slots.
constexpr SampleTime kDifsTicks = 9;
constexpr SampleTime kSlotTicks = 3;

TEST(CsmaMac, ItsFirstFrameWaitsForDifsAndABackoff) {
  // Over many seeds: never before DIFS, on a slot boundary after it, and the
  // backoff drawn (not always 0) from 0..cw_min slots.
  std::set<SampleTime> backoffs;
  for (std::uint64_t seed = 0; seed < 64; ++seed) {
    Station st(find_mac("csma")->info.defaults(), 1, seed);
    st.queue.frames.push_back(NetFrame{1, kBroadcastId, {1, 2, 3}});
    const auto send = st.step_until_send(100);
    ASSERT_TRUE(send);
    const SampleTime tick = (st.now - kTick) / static_cast<SampleTime>(kTick);
    ASSERT_GE(tick, kDifsTicks);
    ASSERT_EQ((tick - kDifsTicks) % kSlotTicks, 0);
    backoffs.insert((tick - kDifsTicks) / kSlotTicks);
    EXPECT_EQ(send->dst, kBroadcastId);
    EXPECT_FALSE(send->awaits_verdict);  // broadcasts are not acknowledged
    EXPECT_EQ(send->header.size(), st.mac->header_bytes());
  }
  EXPECT_LE(*backoffs.rbegin(), 15);
  EXPECT_GE(backoffs.size(), 8U);  // 64 draws from 16 values
}

TEST(CsmaMac, AFrameArrivingToAnIdleChannelGoesAtOnce) {
  Station st;
  st.queue.frames.push_back(NetFrame{1, kBroadcastId, {1}});
  ASSERT_TRUE(st.step_until_send(100));
  // Long after the post-backoff ended: the next frame goes in the tick it arrives.
  for (int i = 0; i < 200; ++i) ASSERT_FALSE(st.step());
  st.queue.frames.push_back(NetFrame{1, kBroadcastId, {2}});
  EXPECT_TRUE(st.step());
}

TEST(CsmaMac, AFrameThatFindsTheChannelBusyDrawsABackoff) {
  // Today's DCF: were no backoff drawn, every such frame would go exactly
  // DIFS after the busy period, on every node at once.
  std::set<SampleTime> waits;
  for (std::uint64_t seed = 0; seed < 64; ++seed) {
    Station st(find_mac("csma")->info.defaults(), 1, seed);
    st.queue.frames.push_back(NetFrame{1, kBroadcastId, {1}});
    ASSERT_TRUE(st.step_until_send(100));
    for (int i = 0; i < 200; ++i) ASSERT_FALSE(st.step());      // the post-backoff is over
    ASSERT_FALSE(st.step(/*busy=*/true));                       // someone else sends
    st.queue.frames.push_back(NetFrame{1, kBroadcastId, {2}});  // and finds it busy
    for (int i = 0; i < 10; ++i) ASSERT_FALSE(st.step(true));
    const SampleTime idle_from = st.now;
    ASSERT_TRUE(st.step_until_send(100));
    const SampleTime wait = (st.now - kTick - idle_from) / static_cast<SampleTime>(kTick);
    ASSERT_GE(wait, kDifsTicks);
    waits.insert(wait);
  }
  EXPECT_GE(waits.size(), 8U);
}

/// Three stations on one channel, each hearing the others' transmissions (and
/// `busy_ticks` of someone else's at the start), each with one broadcast
/// queued at tick 0. True when two of their first transmissions start in the
/// same tick.
bool first_frames_collide(std::uint64_t seed, std::size_t busy_ticks) {
  std::vector<std::unique_ptr<Station>> stations;
  for (NodeId id = 1; id <= 3; ++id) {
    stations.push_back(std::make_unique<Station>(find_mac("csma")->info.defaults(), id, seed));
    stations.back()->queue.frames.push_back(NetFrame{id, kBroadcastId, {1}});
  }
  std::vector<SampleTime> starts(stations.size(), -1);
  for (std::size_t t = 0; t < 1000; ++t) {
    for (std::size_t i = 0; i < stations.size(); ++i) {
      if (stations[i]->decide() && starts[i] < 0) starts[i] = static_cast<SampleTime>(t);
    }
    for (std::size_t i = 0; i < stations.size(); ++i) {
      bool others = t < busy_ticks;
      for (std::size_t j = 0; j < stations.size(); ++j) others |= j != i && stations[j]->on_air();
      stations[i]->sense(others);
    }
  }
  for (const SampleTime s : starts) EXPECT_GE(s, 0) << "seed " << seed;
  return starts[0] == starts[1] || starts[0] == starts[2] || starts[1] == starts[2];
}

TEST(CsmaMac, StationsThatComeUpTogetherRarelyStartTogether) {
  // Backoffs of 0..15 slots: two of three equal with probability 1 - 16 15 14
  // / 16^3 = 18 %. Without the first frame's backoff they always would.
  int collisions = 0;
  for (std::uint64_t seed = 0; seed < 200; ++seed) collisions += first_frames_collide(seed, 0);
  EXPECT_LT(collisions, 60);  // 200 x 18 % = 36
  EXPECT_GT(collisions, 10);  // the draw is random, not a fixed order
}

TEST(CsmaMac, StationsThatQueuedDuringABusyChannelRarelyStartTogether) {
  int collisions = 0;
  for (std::uint64_t seed = 0; seed < 200; ++seed) collisions += first_frames_collide(seed, 40);
  EXPECT_LT(collisions, 60);
}

TEST(CsmaMac, NeverSendsWhileTheChannelIsBusy) {
  Station st;
  st.queue.frames.push_back(NetFrame{1, 2, {1}});
  EXPECT_FALSE(st.step_until_send(500, /*busy=*/true));
  EXPECT_EQ(st.counters.busy_ticks.load(), 500U);
  // Idle again: DIFS and a backoff (at most 15 slots) later it goes.
  EXPECT_TRUE(st.step_until_send(kDifsTicks + 15 * kSlotTicks + 1));
}

TEST(CsmaMac, AnAcknowledgedFrameEndsWithItsVerdictAndABackoff) {
  Station st(csma_with("slot_us", 100.0));  // 1 tick slots: DIFS 3 + 2 = 5 ticks
  st.queue.frames.push_back(NetFrame{1, 2, {9, 9}});
  st.queue.frames.push_back(NetFrame{1, 2, {8}});
  const auto first = st.step_until_send(50);
  ASSERT_TRUE(first);
  EXPECT_TRUE(first->awaits_verdict);
  EXPECT_FALSE(first->retry);
  const std::vector<std::uint8_t> seq(first->header.begin(), first->header.end());
  // Waiting for the ACK: nothing else goes.
  for (int i = 0; i < 5; ++i) EXPECT_FALSE(st.step());
  const std::vector<std::uint8_t> ack = {1, seq[0], seq[1]};
  st.mac->on_control(2, ack, st.now);
  EXPECT_EQ(st.mac->take_verdict(), Verdict::kAcknowledged);
  // The second frame needs DIFS and its backoff: at least 5 ticks.
  const SampleTime acked_at = st.now;
  const auto second = st.step_until_send(3000);
  ASSERT_TRUE(second);
  EXPECT_GE(st.now - kTick - acked_at, 5 * static_cast<SampleTime>(kTick));
  EXPECT_NE(std::vector<std::uint8_t>(second->header.begin(), second->header.end()), seq);
  EXPECT_EQ(st.counters.ack_timeouts.load(), 0U);
}

TEST(CsmaMac, AnAckForAnotherFrameOrFromAnotherNodeIsIgnored) {
  Station st(csma_with("slot_us", 100.0));
  st.queue.frames.push_back(NetFrame{1, 2, {9}});
  const auto first = st.step_until_send(50);
  ASSERT_TRUE(first);
  const std::vector<std::uint8_t> wrong_seq = {1, first->header[0],
                                               static_cast<std::uint8_t>(first->header[1] + 1)};
  st.mac->on_control(2, wrong_seq, st.now);
  EXPECT_FALSE(st.mac->take_verdict());
  const std::vector<std::uint8_t> right = {1, first->header[0], first->header[1]};
  st.mac->on_control(3, right, st.now);  // node 3 never got the frame
  EXPECT_FALSE(st.mac->take_verdict());
  st.mac->on_control(2, std::vector<std::uint8_t>{1, 2}, st.now);  // truncated
  EXPECT_FALSE(st.mac->take_verdict());
}

TEST(CsmaMac, WithoutAckItRetriesUpToTheLimitThenGivesUp) {
  Station st(csma_with("retry_limit", std::uint64_t{3}));
  st.queue.frames.push_back(NetFrame{1, 2, {5, 5, 5}});
  for (std::size_t i = 0; i < 20000 && !st.last_verdict(); ++i) st.step();
  ASSERT_EQ(st.sent.size(), 4U);  // 1 + 3 retries
  EXPECT_FALSE(st.sent[0].t.retry);
  for (std::size_t i = 1; i < 4; ++i) {
    EXPECT_TRUE(st.sent[i].t.retry);
    EXPECT_EQ(st.sent[i].header, st.sent[0].header);  // the same frame, the same sequence number
  }
  EXPECT_EQ(st.last_verdict(), Verdict::kGaveUp);
  EXPECT_EQ(st.counters.retries.load(), 3U);
  EXPECT_EQ(st.counters.ack_timeouts.load(), 4U);
  EXPECT_EQ(st.counters.retry_drops.load(), 1U);
}

TEST(CsmaMac, TheContentionWindowDoublesWithEveryRetry) {
  // Without ACKs every frame is tried 1 + 4 times. The gap before retry k is
  // the ACK wait, DIFS and a backoff drawn from 0..cw_k, cw_k = 31, 63, 127,
  // 255 (cw_min 15): its mean grows by half the window's growth, in slots.
  constexpr std::size_t kFrames = 60;
  Station st(csma_with("retry_limit", std::uint64_t{4}));
  for (std::size_t f = 0; f < kFrames; ++f) st.queue.frames.push_back(NetFrame{1, 2, {1}});
  for (std::size_t i = 0; i < 3'000'000 && st.counters.retry_drops.load() < kFrames; ++i) st.step();
  ASSERT_EQ(st.sent.size(), 5 * kFrames);
  std::vector<double> mean_gap(5, 0.0);
  for (std::size_t f = 0; f < kFrames; ++f) {
    for (std::size_t k = 1; k < 5; ++k) {
      const auto& a = st.sent[5 * f + k - 1];
      const auto& b = st.sent[5 * f + k];
      ASSERT_EQ(a.header, b.header);
      mean_gap[k] += static_cast<double>(b.at - a.at) / kFrames;
    }
  }
  for (std::size_t k = 1; k < 4; ++k) EXPECT_LT(mean_gap[k], mean_gap[k + 1]) << "retry " << k;
  const double slot_samples = 3.0 * kTick;  // 250 us at 100-sample ticks of 1 Msps
  const double expected = (255.0 - 31.0) / 2.0 * slot_samples;
  EXPECT_NEAR(mean_gap[4] - mean_gap[1], expected, 0.3 * expected);
}

TEST(CsmaMac, TheReceiverAcknowledgesAfterSifsAndDropsRepeats) {
  Station st(csma_with("slot_us", 100.0), 2);
  const std::vector<std::uint8_t> header = {0, 7};
  EXPECT_TRUE(st.mac->on_data(1, header, true, st.now).deliver);
  // SIFS (250 us = 3 ticks) after the tick it was decoded in, the ACK goes,
  // whatever carrier sense says.
  std::optional<MacTransmission> ack;
  std::size_t ticks = 0;
  for (; ticks < 10 && !ack; ++ticks) ack = st.step(/*busy=*/true);
  ASSERT_TRUE(ack);
  EXPECT_EQ(ticks - 1, 3U);
  EXPECT_EQ(ack->kind, FrameKind::kMacControl);
  EXPECT_EQ(ack->dst, 1U);
  EXPECT_EQ(std::vector<std::uint8_t>(ack->header.begin(), ack->header.end()),
            (std::vector<std::uint8_t>{1, 0, 7}));
  // The sender missed the ACK and repeats: dropped, and acknowledged again.
  EXPECT_FALSE(st.mac->on_data(1, header, true, st.now).deliver);
  EXPECT_EQ(st.counters.duplicates.load(), 1U);
  EXPECT_TRUE(st.step_until_send(10, true));
  EXPECT_EQ(st.counters.control_sent.load(), 2U);
  // The next sequence number is new; a broadcast is never acknowledged.
  EXPECT_TRUE(st.mac->on_data(1, std::vector<std::uint8_t>{0, 8}, false, st.now).deliver);
  EXPECT_FALSE(st.step_until_send(10, true));
}

}  // namespace
}  // namespace rfsitl::mac
