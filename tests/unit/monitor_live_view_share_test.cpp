// Distributed runs: the live views of two ranks swap what they saw
// (LiveView::share / take_share), so that rank 0's shows every rank's nodes;
// and the coding of a share, with what a reader refuses.
#include "rfsitl/monitor/live_view_share.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "frame_event_builder.hpp"
#include "rfsitl/monitor/live_view.hpp"

namespace rfsitl::monitor {
namespace {

using engine::FrameEventKind;
using engine::testing::frame_event;

LiveViewShare sample_share() {
  LiveViewShare s;
  s.watched = {2};
  s.links = {{1 * 3 + 2, 4, 1}, {2 * 3 + 0, 0, 3}};
  s.spectra.push_back({2, std::vector<float>(LiveView::kSpectrumBins, -20.0F)});
  Constellation c{700, 2, 3, 0x01000009, true, {cf32(1.0F, -1.0F), cf32(-1.0F, 1.0F)}};
  s.constellations.emplace_back(1, c);
  return s;
}

TEST(LiveViewShare, EncodedShareReadsBackAsItWas) {
  const LiveViewShare s = sample_share();
  const LiveViewShare back = decode_share(encode_share(s), 3);
  EXPECT_EQ(back.watched, s.watched);
  ASSERT_EQ(back.links.size(), 2U);
  EXPECT_EQ(back.links[1].cell, 6U);
  EXPECT_EQ(back.links[1].lost, 3U);
  ASSERT_EQ(back.spectra.size(), 1U);
  EXPECT_EQ(back.spectra[0].db, s.spectra[0].db);
  ASSERT_EQ(back.constellations.size(), 1U);
  EXPECT_EQ(back.constellations[0].first, 1U);
  EXPECT_EQ(back.constellations[0].second.serial, 0x01000009U);
  EXPECT_EQ(back.constellations[0].second.points, s.constellations[0].second.points);
  EXPECT_TRUE(back.constellations[0].second.payload_valid);
}

TEST(LiveViewShare, MalformedSharesAreRefusedSayingWhy) {
  const std::vector<std::uint8_t> good = encode_share(sample_share());
  const auto refused = [](std::vector<std::uint8_t> bytes, std::size_t nodes) -> std::string {
    try {
      decode_share(bytes, nodes);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "accepted";
  };
  EXPECT_NE(refused(good, 2).find("watched node index 2 out of range"), std::string::npos);
  auto cut = good;
  cut.pop_back();
  EXPECT_NE(refused(cut, 3).find("count of constellation points beyond its end"),
            std::string::npos);
  cut.resize(10);
  EXPECT_NE(refused(cut, 3).find("short in link cells"), std::string::npos);
  auto longer = good;
  longer.push_back(0);
  EXPECT_NE(refused(longer, 3).find("1 byte(s) after its end"), std::string::npos);
  auto version = good;
  version[0] = 7;
  EXPECT_NE(refused(version, 3).find("format version 7"), std::string::npos);
  LiveViewShare narrow = sample_share();
  narrow.spectra[0].db.resize(8);
  EXPECT_NE(refused(encode_share(narrow), 3).find("8 bins"), std::string::npos);
  LiveViewShare crowded = sample_share();
  crowded.constellations[0].second.points.resize(LiveView::kMaxConstellationPoints + 1);
  EXPECT_NE(refused(encode_share(crowded), 3).find("constellation points"), std::string::npos);
  LiveViewShare far = sample_share();
  far.links[0].cell = 9;
  EXPECT_NE(refused(encode_share(far), 3).find("link cell index 9"), std::string::npos);
}

// Rank 0 owns node index 0, rank 1 nodes 1 and 2 (ids 4, 7, 9).
class TwoRanks : public ::testing::Test {
 protected:
  LiveView rank0{{4, 7, 9}};
  LiveView rank1{{4, 7, 9}};
  void swap() {
    const auto from0 = rank0.share();
    const auto from1 = rank1.share();
    rank1.take_share(0, from0);
    rank0.take_share(1, from1);
  }
};

TEST_F(TwoRanks, LinkOutcomesOfBothRanksAddUpOnEachWithoutCountingTwice) {
  // Serials carry the sender's index in their top byte.
  rank0.on_frame_event(frame_event(FrameEventKind::kReceived, 0, 7, 4, 4, 0x01000001));
  rank1.on_frame_event(frame_event(FrameEventKind::kReceived, 0, 4, 9, 9, 0x00000002));
  rank1.on_frame_event(frame_event(FrameEventKind::kLost, 0, 9, 4, 9, 0x02000003));
  swap();
  auto o = rank0.link_outcomes();
  EXPECT_EQ(o.received[1 * 3 + 0], 1U);  // its own
  EXPECT_EQ(o.received[0 * 3 + 2], 1U);  // rank 1's
  EXPECT_EQ(o.lost[2 * 3 + 0], 1U);
  // Shared again with one more decode: the totals, not the sum of shares.
  rank1.on_frame_event(frame_event(FrameEventKind::kReceived, 0, 4, 9, 9, 0x00000004));
  const auto again = decode_share(rank1.share(), 3);
  ASSERT_EQ(again.links.size(), 1U);  // only the cell that changed
  rank0.take_share(1, encode_share(again));
  swap();
  // Every tenth share carries every cell that is not zero.
  std::size_t most = 0;
  for (int k = 0; k < 10; ++k) most = std::max(most, decode_share(rank1.share(), 3).links.size());
  EXPECT_EQ(most, 2U);
  o = rank0.link_outcomes();
  EXPECT_EQ(o.received[0 * 3 + 2], 2U);
  EXPECT_EQ(o.lost[2 * 3 + 0], 1U);
  EXPECT_EQ(rank1.link_outcomes().received[1 * 3 + 0], 1U);
}

TEST_F(TwoRanks, ANodeWatchedOnRankZeroIsComputedAndItsSpectrumSentByItsOwner) {
  EXPECT_FALSE(rank1.wants_samples(2, 0, 250));
  rank0.watch(2, +1);
  swap();
  ASSERT_TRUE(rank1.wants_samples(2, 0, 250));
  EXPECT_FALSE(rank1.wants_samples(1, 0, 250));
  // A tone at fs/8 in the owner's receiver.
  std::vector<cf32> tone(2048);
  for (std::size_t n = 0; n < tone.size(); ++n) {
    tone[n] =
        std::polar(1.0F, static_cast<float>(2.0 * std::numbers::pi * static_cast<double>(n) / 8.0));
  }
  rank1.on_rx_samples(2, 0, tone);
  swap();
  const std::vector<float> db = rank0.spectrum(2);
  ASSERT_EQ(db.size(), LiveView::kSpectrumBins);
  const auto peak = std::max_element(db.begin(), db.end()) - db.begin();
  EXPECT_EQ(peak, static_cast<long>(LiveView::kSpectrumBins / 2 + LiveView::kSpectrumBins / 8));
  // Unwatched on rank 0: the owner stops keeping the samples.
  rank0.watch(2, -1);
  swap();
  EXPECT_FALSE(rank1.wants_samples(2, 0, 250));
}

TEST_F(TwoRanks, ConstellationsOfAWatchedNodeReachRankZeroAndAnOlderOneDoesNotReplace) {
  rank0.watch(1, +1);
  swap();
  phy::RxEvent ev;
  ev.tag = phy::FrameTag{4, 7, 0x00000011};
  ev.header_valid = true;
  ev.payload_valid = true;
  const std::vector<cf32> symbols(40, cf32(0.5F, -0.5F));
  ev.symbols = symbols;
  rank1.on_decode(1, 900, ev);
  swap();
  auto c = rank0.constellation(1);
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->serial, 0x00000011U);
  EXPECT_EQ(c->points.size(), 40U);
  EXPECT_EQ(c->time, 900);
  // Nothing new: nothing sent; nor for a node nobody watches elsewhere.
  EXPECT_TRUE(decode_share(rank1.share(), 3).constellations.empty());
  rank1.on_decode(2, 950, ev);
  EXPECT_TRUE(decode_share(rank1.share(), 3).constellations.empty());
  // An older decode shared late does not win.
  LiveViewShare old;
  old.constellations.emplace_back(1, Constellation{100, 4, 7, 0x00000001, true, {}});
  rank0.take_share(1, encode_share(old));
  EXPECT_EQ(rank0.constellation(1)->serial, 0x00000011U);
}

TEST_F(TwoRanks, AMalformedShareIsCountedAndChangesNothing) {
  rank1.on_frame_event(frame_event(FrameEventKind::kReceived, 0, 4, 9, 9, 0x00000002));
  swap();
  const auto before = rank0.link_outcomes();
  rank0.take_share(1, std::vector<std::uint8_t>{1, 2});
  EXPECT_EQ(rank0.bad_shares(), 1U);
  EXPECT_EQ(rank0.link_outcomes().received, before.received);
}

}  // namespace
}  // namespace rfsitl::monitor
