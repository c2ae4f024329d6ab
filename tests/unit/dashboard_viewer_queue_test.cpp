// A viewer that reads slowly or never must not grow the server's memory:
// every kind of message (error replies and constellations included) is bounded
// per viewer, and the drops are counted.
#include "rfsitl/monitor/viewer_queue.hpp"

#include <gtest/gtest.h>

#include <chrono>

#include "dashboard_test_support.hpp"

namespace rfsitl::monitor {
namespace {

namespace http = test::http;

OutgoingMessage message(const std::string& text, MessageKind kind, bool snr = false) {
  return {std::make_shared<const std::string>(text), kind, snr};
}

std::vector<std::string> drain(ViewerQueue& q) {
  std::vector<std::string> out;
  while (!q.empty()) {
    out.push_back(*q.start_front().text);
    q.pop_front();
  }
  return out;
}

TEST(DashboardViewerQueue, EventsBeyondTheCapacityDropTheOldestButNeverTheOneBeingWritten) {
  ViewerQueue q;
  q.push(message("hello", MessageKind::kEssential));
  q.push(message("e0", MessageKind::kEvent));
  ASSERT_EQ(*q.start_front().text, "hello");  // being written
  std::size_t dropped = 0;
  for (int i = 1; i < 1000; ++i)
    dropped += q.push(message("e" + std::to_string(i), MessageKind::kEvent));
  EXPECT_EQ(q.size(), ViewerQueue::kCapacity);
  EXPECT_EQ(q.peak(), ViewerQueue::kCapacity);
  EXPECT_EQ(dropped, 1000 + 1 - ViewerQueue::kCapacity);
  EXPECT_EQ(q.dropped(), dropped);
  const auto left = drain(q);
  ASSERT_EQ(left.size(), ViewerQueue::kCapacity);
  EXPECT_EQ(left.front(), "hello");
  EXPECT_EQ(left[1], "e" + std::to_string(1000 - ViewerQueue::kCapacity + 1));  // oldest gone
  EXPECT_EQ(left.back(), "e999");
}

TEST(DashboardViewerQueue, ANewerSnapshotOrSpectrumReplacesTheQueuedOne) {
  ViewerQueue q;
  q.push(message("s0", MessageKind::kSnapshot, true));
  q.start_front();  // s0 is being written: it stays
  q.push(message("s1", MessageKind::kSnapshot, true));
  q.push(message("f1", MessageKind::kSpectrum));
  q.push(message("c1", MessageKind::kEvent));
  EXPECT_FALSE(q.take_lost_snr());
  q.push(message("s2", MessageKind::kSnapshot, false));  // s1 had the matrix, s2 has not
  EXPECT_TRUE(q.take_lost_snr());
  EXPECT_FALSE(q.take_lost_snr());  // reading clears it
  q.push(message("f2", MessageKind::kSpectrum));
  EXPECT_EQ(q.dropped(), 2U);
  EXPECT_EQ(drain(q), (std::vector<std::string>{"s0", "c1", "s2", "f2"}));
}

TEST(DashboardViewerQueue, AViewerThatNeverReadsKeepsABoundedQueueAndIsCounted) {
  DashboardSettings settings;
  settings.push_interval_s = 3600;  // only the replies to its own messages
  test::LiveDashboard d(settings);
  test::Viewer v;
  // Default socket buffers: a tiny SO_RCVBUF makes loopback TCP drop segments
  // and back off for seconds, which would stall the client, not the server.
  const auto ec = v.connect(d.port());
  ASSERT_FALSE(ec) << ec.message();
  // Each bad message earns an error reply it never reads; the socket buffers
  // fill (a few MB), then the server's queue. That takes 3 s under ASan and
  // over 30 s under ThreadSanitizer beside other tests: a generous deadline.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  std::size_t sent = 0;
  bool server_reads = true;
  while (server_reads && d.dashboard->messages_dropped() == 0 &&
         std::chrono::steady_clock::now() < deadline) {
    for (int i = 0; i < 100 && server_reads; ++i, ++sent) {
      server_reads = v.write_for("?", std::chrono::seconds(20));
    }
  }
  ASSERT_TRUE(server_reads) << "the server stopped reading after " << sent << " messages ("
                            << d.dashboard->messages_dropped() << " dropped, peak queue "
                            << d.dashboard->peak_send_queue() << ")";
  EXPECT_GT(d.dashboard->messages_dropped(), 0U) << sent << " messages sent";
  EXPECT_LE(d.dashboard->peak_send_queue(), ViewerQueue::kCapacity) << sent << " messages sent";
  // Still serving, and says so.
  const auto metrics = test::request(d.port(), http::verb::get, "/metrics");
  EXPECT_NE(metrics.body().find("rfsitl_dashboard_messages_dropped_total "), std::string::npos);
  EXPECT_EQ(metrics.body().find("rfsitl_dashboard_messages_dropped_total 0\n"), std::string::npos);
  // The viewer that finally reads gets its hello first.
  EXPECT_NE(v.read().find("\"hello\""), std::string::npos);
}

}  // namespace
}  // namespace rfsitl::monitor
