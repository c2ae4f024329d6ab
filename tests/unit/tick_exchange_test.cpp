// The messages of a distributed run's tick: what is written is read back, and
// short or inconsistent bytes are refused naming the rank (never read past).
#include "tick_exchange.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <stdexcept>

namespace rfsitl::engine {
namespace {

TEST(TickExchange, TxMessageRoundTrips) {
  TxMessage m;
  m.stop = true;
  TxReport a;
  a.node = 3;
  a.tx_samples = 4;
  a.started = true;
  a.serial = 0x03000007;
  a.dst = 255;
  a.kind = 2;
  a.started_len = 1704;
  a.awaits_verdict = true;
  a.first_attempt = false;
  a.mac_frame = 0x03000005;
  TxReport b;
  b.node = 1;
  b.has_verdict = true;
  b.gave_up = true;
  b.verdict_frame = 0x01000002;
  const std::vector<cf32> samples{{1, 2}, {3, 4}, {5, 6}, {7, 8}};
  m.reports = {a, b};
  m.samples = {samples, {}};
  StateUpdate u;
  u.node = 2;
  u.moves = true;
  u.position = Ecef{1.5, -2.5, 6.4e6};
  u.motion.attitude = position::Attitude{0.1, 0.2, 0.3};
  StateUpdate gone;
  gone.node = 0;
  gone.moves = true;  // position unknown
  m.updates = {u, gone};
  std::vector<std::uint8_t> bytes;
  write_tx_message(m, bytes);

  const TxMessageView v = read_tx_message(bytes, 1, 4, 250);
  EXPECT_TRUE(v.stop);
  ASSERT_EQ(v.reports.size(), 2U);
  EXPECT_EQ(v.reports[0].serial, a.serial);
  EXPECT_EQ(v.reports[0].dst, a.dst);
  EXPECT_EQ(v.reports[0].kind, a.kind);
  EXPECT_EQ(v.reports[0].started_len, a.started_len);
  EXPECT_EQ(v.reports[0].mac_frame, a.mac_frame);
  EXPECT_TRUE(v.reports[0].awaits_verdict);
  EXPECT_FALSE(v.reports[0].first_attempt);
  EXPECT_FALSE(v.reports[0].has_verdict);
  EXPECT_TRUE(v.reports[1].has_verdict);
  EXPECT_TRUE(v.reports[1].gave_up);
  EXPECT_EQ(v.reports[1].verdict_frame, b.verdict_frame);
  EXPECT_FALSE(v.reports[1].started);
  std::vector<cf32> back(4);
  std::memcpy(back.data(), bytes.data() + v.sample_offsets[0], 4 * sizeof(cf32));
  EXPECT_EQ(back, samples);
  ASSERT_EQ(v.updates.size(), 2U);
  EXPECT_EQ(v.updates[0].node, 2U);
  ASSERT_TRUE(v.updates[0].position);
  EXPECT_EQ(v.updates[0].position->z, 6.4e6);
  EXPECT_EQ(v.updates[0].motion.attitude, u.motion.attitude);
  EXPECT_FALSE(v.updates[0].motion.velocity);
  EXPECT_TRUE(v.updates[1].moves);
  EXPECT_FALSE(v.updates[1].position);
}

TEST(TickExchange, EveryTruncationIsRefusedNamingTheRank) {
  TxMessage m;
  TxReport a;
  a.node = 0;
  a.tx_samples = 2;
  const std::vector<cf32> samples(2);
  m.reports = {a};
  m.samples = {samples};
  std::vector<std::uint8_t> bytes;
  write_tx_message(m, bytes);
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    const std::span<const std::uint8_t> cut(bytes.data(), n);
    try {
      (void)read_tx_message(cut, 3, 4, 250);
      ADD_FAILURE() << "a message cut to " << n << " bytes was read";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("rank 3"), std::string::npos) << e.what();
    }
  }
  bytes.push_back(0);
  EXPECT_THROW((void)read_tx_message(bytes, 0, 4, 250), std::runtime_error);
}

TEST(TickExchange, NodesAndSampleCountsOutOfRangeAreRefused) {
  TxMessage m;
  TxReport a;
  a.node = 9;
  m.reports = {a};
  m.samples = {{}};
  std::vector<std::uint8_t> bytes;
  write_tx_message(m, bytes);
  EXPECT_THROW((void)read_tx_message(bytes, 0, 4, 250), std::runtime_error);  // 4 nodes
  EXPECT_NO_THROW((void)read_tx_message(bytes, 0, 10, 250));

  a.node = 0;
  a.tx_samples = 300;
  const std::vector<cf32> samples(300);
  m.reports = {a};
  m.samples = {samples};
  write_tx_message(m, bytes);
  EXPECT_THROW((void)read_tx_message(bytes, 0, 4, 250), std::runtime_error);  // over a tick
}

TEST(TickExchange, LedgerOpsAndCountersRoundTrip) {
  const std::vector<LedgerOp> ops{{2, LedgerOp::Kind::kDecoded, false, 77, 5},
                                  {3, LedgerOp::Kind::kFrameDone, true, 78, LedgerOp::kNoDelivery}};
  std::vector<std::uint8_t> bytes;
  write_ledger_ops(ops, bytes);
  std::vector<LedgerOp> back;
  read_ledger_ops(bytes, 1, 4, back);
  ASSERT_EQ(back.size(), 2U);
  EXPECT_EQ(back[0].node, 2U);
  EXPECT_EQ(back[0].id, 77U);
  EXPECT_EQ(back[0].delivery, LedgerOp::kNoDelivery);  // a delivery stays with its owner
  EXPECT_EQ(back[1].kind, LedgerOp::Kind::kFrameDone);
  EXPECT_TRUE(back[1].gave_up);
  bytes[4 + 4] = 9;  // an unknown op
  back.clear();
  EXPECT_THROW(read_ledger_ops(bytes, 1, 4, back), std::runtime_error);

  NodeCountersSnapshot c;
  c.delivered = 5;
  c.lost[2] = 3;
  c.mac.retries = 4;
  const std::vector<std::pair<std::uint32_t, NodeCountersSnapshot>> own{{1, c}};
  const std::vector<ObserverShare> shares{{"live_view", {1, 2, 3}}, {"empty", {}}};
  write_counters(RankFigures{0.5, 2, 1000, 0.25, 3.0}, own, shares, bytes);
  RankFigures f;
  std::vector<std::pair<std::uint32_t, NodeCountersSnapshot>> all;
  std::vector<ObserverShare> got;
  read_counters(bytes, 0, 4, f, all, got);
  EXPECT_EQ(f.exchanged_bytes, 1000U);
  EXPECT_EQ(f.max_lag_s, 0.5);
  ASSERT_EQ(all.size(), 1U);
  EXPECT_EQ(all[0].second.lost[2], 3U);
  EXPECT_EQ(all[0].second.mac.retries, 4U);
  ASSERT_EQ(got.size(), 2U);
  EXPECT_EQ(got[0].key, "live_view");
  EXPECT_EQ(got[0].bytes, (std::vector<std::uint8_t>{1, 2, 3}));
  EXPECT_EQ(got[1].key, "empty");
  EXPECT_TRUE(got[1].bytes.empty());
  // A share longer than what is left, and a byte cut off the end: refused.
  std::vector<std::uint8_t> lying = bytes;
  lying[lying.size() - 4] = 200;  // the last share's length
  got.clear();
  all.clear();
  EXPECT_THROW(read_counters(lying, 0, 4, f, all, got), std::runtime_error);
  bytes.pop_back();
  got.clear();
  all.clear();
  EXPECT_THROW(read_counters(bytes, 0, 4, f, all, got), std::runtime_error);
}

}  // namespace
}  // namespace rfsitl::engine
