#include "rfsitl/monitor/live_view.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "frame_event_builder.hpp"

namespace rfsitl::monitor {
namespace {

using engine::FrameEventKind;
using engine::testing::frame_event;

TEST(LiveView, WatchedNodeWantsFourTicksInSixteenAndOthersNone) {
  LiveView view({1, 2, 3});
  EXPECT_FALSE(view.wants_samples(1, 0, 250));
  view.watch(1, +1);
  std::size_t wanted = 0;
  for (std::size_t k = 0; k < 64; ++k) wanted += view.wants_samples(1, k * 250, 250) ? 1 : 0;
  EXPECT_EQ(wanted, 64U * 4 / 16);
  EXPECT_TRUE(view.wants_samples(1, 0, 250));
  EXPECT_FALSE(view.wants_samples(0, 0, 250));
  view.watch(1, -1);
  EXPECT_FALSE(view.wants_samples(1, 0, 250));
}

TEST(LiveView, LinkOutcomesCountReceivedAtTheReceiverAndLostAtTheDestination) {
  LiveView view({4, 7, 9});
  // Serials carry the sender's index in their top byte (node 7 is index 1).
  view.on_frame_event(frame_event(FrameEventKind::kReceived, 0, 7, 9, 9, 0x01000001));
  view.on_frame_event(frame_event(FrameEventKind::kLost, 0, 7, 4, 7, 0x01000002));
  view.on_frame_event(frame_event(FrameEventKind::kLost, 0, 7, 255, 7, 0x01000003));  // broadcast
  view.on_frame_event(frame_event(FrameEventKind::kTransmitted, 0, 7, 9, 7, 0x01000004));
  const auto o = view.link_outcomes();
  EXPECT_EQ(o.received[1 * 3 + 2], 1U);
  EXPECT_EQ(o.lost[1 * 3 + 0], 1U);
  std::uint32_t total = 0;
  for (const auto v : o.received) total += v;
  for (const auto v : o.lost) total += v;
  EXPECT_EQ(total, 2U);  // the broadcast loss and the transmission count on no link
}

TEST(LiveView, SpectrumIsPublishedOnlyAfterAFullBlockAndConstellationKeepsAtMost512Points) {
  LiveView view({1, 2});
  view.watch(0, +1);
  view.on_rx_samples(0, 0, std::vector<cf32>(100, cf32(1.0F)));
  view.publish_spectra();
  EXPECT_TRUE(view.spectrum(0).empty());
  view.on_rx_samples(0, 100, std::vector<cf32>(400, cf32(1.0F)));
  view.publish_spectra();
  EXPECT_EQ(view.spectrum(0).size(), LiveView::kSpectrumBins);
  const std::vector<cf32> symbols(2000, cf32(0.5F, -0.5F));
  phy::RxEvent ev;
  ev.tag = phy::FrameTag{2, 1, 0x01000005};
  ev.header_valid = true;
  ev.payload_valid = true;
  ev.symbols = symbols;
  view.on_decode(0, 500, ev);
  const auto c = view.constellation(0);
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->points.size(), LiveView::kMaxConstellationPoints);
  EXPECT_EQ(c->serial, 0x01000005U);
  EXPECT_FALSE(view.constellation(1).has_value());
}

}  // namespace
}  // namespace rfsitl::monitor
