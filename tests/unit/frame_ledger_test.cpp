#include "rfsitl/engine/frame_ledger.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <random>
#include <vector>

#include "rfsitl/channel/stages/path_loss.hpp"
#include "rfsitl/engine/node_counters.hpp"

namespace rfsitl::engine {
namespace {

// Paper model, exponent 3: |c|^2 = (d + 1)^-6, so with sigma^2 = 1e-12 the SNR
// is 120 - 60 log10(d + 1) dB: 10 dB (the sensitivity) at d = 67.1 m.
constexpr double kNoise = 1e-12;
constexpr double kSensitivityDb = 10.0;
constexpr SampleTime kGrace = 100;
constexpr SampleTime kLen = 2000;

std::size_t idx(LossReason r) {
  return static_cast<std::size_t>(r);
}

/// Nodes on a straight line at x metres (nullopt: no position); node index i has id i + 1.
class World {
 public:
  explicit World(const std::vector<std::optional<double>>& xs)
      : channel(xs.size(), channel::make_paper_budget(3.0)),
        counters(xs.size()),
        ledger(LedgerConfig{kNoise, std::vector<double>(xs.size(), kSensitivityDb), kGrace, {}},
               counters, [n = xs.size()](NodeId id) -> std::optional<std::size_t> {
                 if (id >= 1 && id <= n) return static_cast<std::size_t>(id - 1);
                 return std::nullopt;
               }) {
    for (std::size_t i = 0; i < xs.size(); ++i) {
      if (xs[i]) channel.set_position(i, Ecef{6378137.0 + *xs[i], 0.0, 0.0});
    }
  }
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  NodeCountersSnapshot at(std::size_t i) const { return counters[i].snapshot(); }
  std::uint64_t lost(std::size_t i, LossReason r) const { return at(i).lost[idx(r)]; }
  void settle_all() { ledger.settle(1'000'000'000, channel); }

  channel::ChannelMatrix channel;
  std::vector<NodeCounters> counters;
  FrameLedger ledger;
};

TEST(FrameLedger, UnicastDecodedByItsDestinationIsDelivered) {
  World w({0.0, 5.0});
  w.ledger.on_transmit(1, 0, 2, 0, kLen);
  EXPECT_EQ(w.at(0).transmitted, 1U);
  EXPECT_EQ(w.ledger.in_flight(), 1U);
  EXPECT_TRUE(w.ledger.on_decoded(1, 1));
  EXPECT_EQ(w.at(0).delivered, 1U);
  EXPECT_EQ(w.ledger.in_flight(), 0U);
  w.settle_all();
  EXPECT_EQ(w.at(0).delivered, 1U);
  EXPECT_EQ(w.at(0).lost_total(), 0U);
}

TEST(FrameLedger, DecodeByTransmitterBystanderOrUnknownSerialIsNotHandedOver) {
  World w({0.0, 5.0, 10.0});
  w.ledger.on_transmit(1, 0, 2, 0, kLen);
  EXPECT_FALSE(w.ledger.on_decoded(1, 0));   // its own transmitter
  EXPECT_FALSE(w.ledger.on_decoded(1, 2));   // node 3 is not the destination
  EXPECT_FALSE(w.ledger.on_decoded(99, 1));  // no such frame
  EXPECT_EQ(w.at(0).delivered, 0U);
  EXPECT_EQ(w.ledger.in_flight(), 1U);
  w.settle_all();
  EXPECT_EQ(w.lost(0, LossReason::kDecodeFailure), 1U);
}

TEST(FrameLedger, UndecodedWhileReceiverTransmittedIsHalfDuplexForBoth) {
  World w({0.0, 5.0});
  w.ledger.on_transmit(1, 0, 2, 0, kLen);
  w.ledger.on_transmit(2, 1, 1, kLen - 1, 2 * kLen);  // overlaps by one sample
  w.settle_all();
  EXPECT_EQ(w.lost(0, LossReason::kHalfDuplex), 1U);
  EXPECT_EQ(w.lost(1, LossReason::kHalfDuplex), 1U);
}

TEST(FrameLedger, ReceiverBeyondSensitivityRangeOrWithoutPositionIsBelowSensitivity) {
  World w({0.0, 60.0, 75.0, 200.0, std::nullopt});
  // 60 m: SNR 12.9 dB (above); 75 m: 7.2 dB; 200 m: -18 dB; no position: no link.
  SampleTime t = 0;
  for (const NodeId dst : std::vector<NodeId>{2, 3, 4, 5}) {
    w.ledger.on_transmit(dst, 0, dst, t, t + kLen);
    t += 10 * kLen;
  }
  w.settle_all();
  EXPECT_EQ(w.lost(0, LossReason::kDecodeFailure), 1U);
  EXPECT_EQ(w.lost(0, LossReason::kBelowSensitivity), 3U);
  EXPECT_EQ(w.at(0).lost_total(), 4U);
}

TEST(FrameLedger, OverlappingEqualPowerFrameFromThirdNodeIsCollision) {
  World w({-5.0, 0.0, 5.0});
  w.ledger.on_transmit(1, 0, 2, 0, kLen);
  w.ledger.on_transmit(2, 2, 2, kLen / 2, kLen / 2 + kLen);
  w.settle_all();
  EXPECT_EQ(w.lost(0, LossReason::kCollision), 1U);
  EXPECT_EQ(w.lost(2, LossReason::kCollision), 1U);
}

TEST(FrameLedger, BackToBackOrInaudibleInterfererIsNotCollision) {
  World w({-5.0, 0.0, 5.0, 100000.0});
  w.ledger.on_transmit(1, 0, 2, 0, kLen);
  w.ledger.on_transmit(2, 2, 2, kLen, 2 * kLen);  // [0, L) and [L, 2L) do not overlap
  // Node 4 at 100 km reaches node 2 far below the noise floor.
  w.ledger.on_transmit(3, 0, 2, 10 * kLen, 11 * kLen);
  w.ledger.on_transmit(4, 3, 2, 10 * kLen, 11 * kLen);
  w.settle_all();
  EXPECT_EQ(w.lost(0, LossReason::kDecodeFailure), 2U);
  EXPECT_EQ(w.lost(2, LossReason::kDecodeFailure), 1U);
  EXPECT_EQ(w.lost(3, LossReason::kBelowSensitivity), 1U);
}

TEST(FrameLedger, ExternalActivityOverlappingAFrameIsCollisionAndIsNeverCounted) {
  World w({-5.0, 0.0, 5.0});
  // Node 3 (an external program) transmits in two adjoining ticks, then stops.
  w.ledger.on_activity(2, 0, 250);
  w.ledger.on_activity(2, 250, 500);
  w.ledger.on_transmit(1, 0, 2, 400, 400 + kLen);       // overlaps the second tick
  w.ledger.on_transmit(2, 0, 2, 10 * kLen, 11 * kLen);  // long after: clean
  w.settle_all();
  EXPECT_EQ(w.lost(0, LossReason::kCollision), 1U);
  EXPECT_EQ(w.lost(0, LossReason::kDecodeFailure), 1U);
  EXPECT_EQ(w.at(2).transmitted, 0U);  // activity is not a frame
  EXPECT_EQ(w.at(2).lost_total(), 0U);
}

TEST(FrameLedger, ActivityOfTheReceiverItselfIsHalfDuplexAndSerialZeroStillDecodes) {
  World w({0.0, 5.0});
  w.ledger.on_activity(1, 0, 250);
  w.ledger.on_transmit(0, 0, 2, 100, 100 + kLen);  // serial 0, like the engine's first frame
  w.ledger.on_transmit(7, 0, 2, 10 * kLen, 11 * kLen);
  EXPECT_TRUE(w.ledger.on_decoded(7, 1));
  w.settle_all();
  EXPECT_EQ(w.lost(0, LossReason::kHalfDuplex), 1U);
  EXPECT_EQ(w.at(0).delivered, 1U);
  World v({0.0, 5.0});
  v.ledger.on_activity(1, 0, 250);
  v.ledger.on_transmit(0, 0, 2, 10 * kLen, 11 * kLen);
  EXPECT_TRUE(v.ledger.on_decoded(0, 1));  // the activity record does not shadow serial 0
}

TEST(FrameLedger, OutcomeCallbackReportsEachFrameOnceWithItsReason) {
  World w({-5.0, 0.0, 5.0});
  std::vector<LedgerOutcome> seen;
  w.ledger.set_outcome_callback([&](const LedgerOutcome& o) { seen.push_back(o); });
  w.ledger.on_transmit(1, 0, 2, 0, kLen);
  w.ledger.on_transmit(2, 2, 2, kLen / 2, kLen / 2 + kLen);
  w.ledger.on_transmit(3, 0, 3, 10 * kLen, 11 * kLen);
  EXPECT_TRUE(w.ledger.on_decoded(3, 2));
  w.settle_all();
  ASSERT_EQ(seen.size(), 3U);
  EXPECT_TRUE(seen[0].delivered);  // the decode comes first
  EXPECT_EQ(seen[0].serial, 3U);
  EXPECT_EQ(seen[0].rx, std::optional<std::size_t>(2));
  for (std::size_t i = 1; i < 3; ++i) {
    EXPECT_FALSE(seen[i].delivered);
    EXPECT_EQ(seen[i].reason, LossReason::kCollision);
    EXPECT_EQ(seen[i].rx, std::optional<std::size_t>(1));
    EXPECT_EQ(seen[i].end - seen[i].start, kLen);
  }
}

TEST(FrameLedger, UndecodedFrameWithNothingWrongIsDecodeFailure) {
  World w({0.0, 5.0});
  w.ledger.on_transmit(1, 0, 2, 0, kLen);
  w.settle_all();
  EXPECT_EQ(w.lost(0, LossReason::kDecodeFailure), 1U);
  EXPECT_EQ(w.at(0).lost_total(), 1U);
  EXPECT_EQ(w.at(0).delivered, 0U);
}

TEST(FrameLedger, FrameToUnknownIdIsUnknownDestination) {
  World w({0.0, 5.0});
  w.ledger.on_transmit(1, 0, 99, 0, kLen);
  EXPECT_FALSE(w.ledger.on_decoded(1, 1));
  w.settle_all();
  EXPECT_EQ(w.lost(0, LossReason::kUnknownDestination), 1U);
}

TEST(FrameLedger, LoneNodesBroadcastHasNoLinkSoIsBelowSensitivity) {
  World w({0.0});
  w.ledger.on_transmit(1, 0, kBroadcastId, 0, kLen);
  w.settle_all();
  EXPECT_EQ(w.lost(0, LossReason::kBelowSensitivity), 1U);
  EXPECT_EQ(w.lost(0, LossReason::kUnknownDestination), 0U);
}

TEST(FrameLedger, BroadcastDecodedByAnyReceiverIsDeliveredOnceAtSettle) {
  World w({0.0, 5.0, 10.0});
  w.ledger.on_transmit(1, 0, kBroadcastId, 0, kLen);
  EXPECT_TRUE(w.ledger.on_decoded(1, 1));
  EXPECT_TRUE(w.ledger.on_decoded(1, 2));
  EXPECT_EQ(w.at(0).delivered, 0U);  // waits for every receiver's verdict
  EXPECT_EQ(w.ledger.in_flight(), 1U);
  w.ledger.settle(kLen + kGrace, w.channel);
  EXPECT_EQ(w.at(0).delivered, 1U);
  EXPECT_EQ(w.at(0).lost_total(), 0U);
  EXPECT_EQ(w.ledger.in_flight(), 0U);
}

TEST(FrameLedger, BroadcastDecodedByNobodyIsLostWithBestReceiversReason) {
  World w({0.0, 5.0, 300.0});
  w.ledger.on_transmit(1, 0, kBroadcastId, 0, kLen);
  w.settle_all();
  EXPECT_EQ(w.at(0).delivered, 0U);
  EXPECT_EQ(w.lost(0, LossReason::kDecodeFailure), 1U);  // node 2 at 5 m had a good link

  World far({0.0, 300.0, 400.0});
  far.ledger.on_transmit(1, 0, kBroadcastId, 0, kLen);
  far.settle_all();
  EXPECT_EQ(far.lost(0, LossReason::kBelowSensitivity), 1U);
}

TEST(FrameLedger, DecodeAfterSettleIsNotDeliveredAndCountsAsLate) {
  World w({0.0, 5.0});
  w.ledger.on_transmit(1, 0, 2, 0, kLen);
  w.ledger.settle(kLen + kGrace, w.channel);
  EXPECT_EQ(w.lost(0, LossReason::kDecodeFailure), 1U);
  EXPECT_FALSE(w.ledger.on_decoded(1, 1));
  EXPECT_EQ(w.ledger.late_decodes(), 1U);
  EXPECT_EQ(w.at(0).delivered, 0U);
  EXPECT_EQ(w.at(0).lost_total(), 1U);
}

TEST(FrameLedger, SettleWaitsUntilEndPlusGrace) {
  World w({0.0, 5.0});
  w.ledger.on_transmit(1, 0, 2, 0, kLen);
  w.ledger.on_transmit(2, 0, 2, 10 * kLen, 11 * kLen);
  w.ledger.settle(kLen + kGrace - 1, w.channel);
  EXPECT_EQ(w.at(0).lost_total(), 0U);
  EXPECT_EQ(w.ledger.in_flight(), 2U);
  EXPECT_TRUE(w.ledger.on_decoded(1, 1));  // a decode just inside the grace still counts
  EXPECT_EQ(w.at(0).delivered, 1U);
  w.ledger.settle(11 * kLen + kGrace - 1, w.channel);
  EXPECT_EQ(w.ledger.in_flight(), 1U);
  w.ledger.settle(11 * kLen + kGrace, w.channel);
  EXPECT_EQ(w.ledger.in_flight(), 0U);
  EXPECT_EQ(w.lost(0, LossReason::kDecodeFailure), 1U);
  EXPECT_EQ(w.ledger.late_decodes(), 0U);
}

TEST(FrameLedger, EverySettledFrameIsEitherDeliveredOrLost) {
  World w({0.0, 5.0, 30.0, 150.0, std::nullopt});
  std::mt19937 rng(2024);
  const std::vector<NodeId> dsts{1, 2, 3, 4, 5, kBroadcastId, 77};
  std::vector<SampleTime> busy_until(5, 0);
  std::uint32_t serial = 0;
  std::uint64_t decodes_handed_over = 0;
  for (SampleTime now = 0; now < 400 * kLen; now += kLen / 4) {
    for (std::size_t tx = 0; tx < 5; ++tx) {
      if (busy_until[tx] > now || rng() % 8 != 0) continue;
      const SampleTime len = kLen / 2 + static_cast<SampleTime>(rng() % kLen);
      w.ledger.on_transmit(++serial, tx, dsts[rng() % dsts.size()], now, now + len);
      busy_until[tx] = now + len;
    }
    // Random decodes of random recent serials by random receivers.
    for (int k = 0; k < 3 && serial > 0; ++k) {
      const std::uint32_t s = serial - static_cast<std::uint32_t>(rng() % std::min(serial, 6U));
      decodes_handed_over += w.ledger.on_decoded(s, rng() % 5) ? 1 : 0;
    }
    w.ledger.settle(now, w.channel);
  }
  w.settle_all();
  EXPECT_EQ(w.ledger.in_flight(), 0U);
  std::uint64_t transmitted = 0;
  std::uint64_t delivered = 0;
  for (std::size_t i = 0; i < 5; ++i) {
    const auto s = w.at(i);
    EXPECT_EQ(s.transmitted, s.delivered + s.lost_total()) << "node " << i;
    transmitted += s.transmitted;
    delivered += s.delivered;
  }
  EXPECT_EQ(transmitted, serial);
  EXPECT_GT(delivered, 0U);
  EXPECT_LT(delivered, transmitted);
  EXPECT_GE(decodes_handed_over, delivered);  // broadcasts may be handed to several nodes
}

// A MAC's frame sent in attempts (serials 10, 11, 12 of frame 10): counted once.

TEST(FrameLedgerAttempts, TheFirstDecodedAttemptDeliversTheFrameOnce) {
  World w({0.0, 5.0});
  w.ledger.on_transmit(10, 0, 2, 0, kLen, 10);
  w.ledger.settle(kLen + kGrace, w.channel);  // the first attempt was not decoded
  EXPECT_EQ(w.at(0).lost_total(), 0U) << "the MAC may still retry";
  w.ledger.on_transmit(11, 0, 2, 3 * kLen, 4 * kLen, 10);
  EXPECT_TRUE(w.ledger.on_decoded(11, 1));
  EXPECT_EQ(w.at(0).delivered, 1U);
  // Its ACK was lost: the MAC sends a third attempt, decoded again (a repeat).
  w.ledger.on_transmit(12, 0, 2, 6 * kLen, 7 * kLen, 10);
  EXPECT_TRUE(w.ledger.on_decoded(12, 1)) << "handed to the MAC, which drops the repeat";
  w.ledger.on_frame_done(10, false);
  w.settle_all();
  EXPECT_EQ(w.at(0).transmitted, 3U);
  EXPECT_EQ(w.at(0).delivered, 1U);
  EXPECT_EQ(w.at(0).lost_total(), 0U);
  EXPECT_EQ(w.ledger.in_flight(), 0U);
}

TEST(FrameLedgerAttempts, AFrameGivenUpIsLostOnceWithTheRetryLimitReason) {
  World w({0.0, 5.0});
  for (std::uint32_t k = 0; k < 3; ++k) {
    const SampleTime start = 3 * kLen * k;
    w.ledger.on_transmit(20 + k, 0, 2, start, start + kLen, 20);
    w.ledger.settle(start + kLen + kGrace, w.channel);
  }
  EXPECT_EQ(w.at(0).lost_total(), 0U);
  w.ledger.on_frame_done(20, true);
  EXPECT_EQ(w.lost(0, LossReason::kRetryLimit), 1U);
  EXPECT_EQ(w.at(0).lost_total(), 1U);
  EXPECT_EQ(w.at(0).transmitted, 3U);
}

TEST(FrameLedgerAttempts, AVerdictBeforeTheLastAttemptSettlesWaitsForIt) {
  World w({0.0, 5.0});
  w.ledger.on_transmit(30, 0, 2, 0, kLen, 30);
  w.ledger.on_frame_done(30, true);
  EXPECT_EQ(w.at(0).lost_total(), 0U) << "the attempt still awaits its receiver's verdict";
  w.ledger.settle(kLen + kGrace, w.channel);
  EXPECT_EQ(w.lost(0, LossReason::kRetryLimit), 1U);
}

TEST(FrameLedgerAttempts, AcknowledgedButNeverDecodedKeepsThePhysicalReason) {
  // (Only a late decode can make this happen; the books still close.)
  World w({0.0, 500.0});  // far below sensitivity
  w.ledger.on_transmit(40, 0, 2, 0, kLen, 40);
  w.ledger.settle(kLen + kGrace, w.channel);
  w.ledger.on_frame_done(40, false);
  EXPECT_EQ(w.lost(0, LossReason::kBelowSensitivity), 1U);
}

}  // namespace
}  // namespace rfsitl::engine
