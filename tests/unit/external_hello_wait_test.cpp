/// Connections that have not said hello yet wait side by side, each with its
/// own deadline: however many are silent, a node that says hello at once is
/// admitted at once (a rejoin is not delayed by hello_timeout_ms per silent
/// connection), and each silent one is refused when its own time is up.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

#include "external_test_support.hpp"
#include "rfsitl/external/client/external_client.hpp"
#include "rfsitl/external/client/message_channel.hpp"
#include "rfsitl/external/external_hub.hpp"

namespace rfsitl::external {
namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;
using testing::SocketPath;

constexpr NodeId kNode = 2;

HubSettings hub_settings(const std::string& path, int hello_timeout_ms) {
  HubSettings s;
  s.socket_path = path;
  s.hello_timeout_ms = hello_timeout_ms;
  return s;
}

std::vector<ExternalNodeSpec> one_node() {
  return {ExternalNodeSpec{0, kNode, Role::kSamples, ""}};
}

struct Silent {
  MessageChannel channel;
  Clock::time_point opened;
};

TEST(ExternalHelloWait, SilentConnectionsDoNotDelayAGoodHello) {
  SocketPath path;
  constexpr int kHelloTimeoutMs = 1000;
  constexpr milliseconds kHelloTimeout{kHelloTimeoutMs};
  const auto hub = make_external_hub(hub_settings(path.str(), kHelloTimeoutMs), one_node());

  // Handled one after another, these would hold the hub for 6 hello timeouts.
  constexpr int kSilent = 6;
  std::vector<Silent> silent;
  for (int i = 0; i < kSilent; ++i) {
    silent.push_back({MessageChannel::connect_to(path.str()), Clock::now()});
  }
  ExternalClient good({path.str(), kNode, "samples", "unit-test", 10 * kHelloTimeoutMs});
  const auto t0 = Clock::now();
  good.connect();
  const auto joined_after = Clock::now() - t0;
  // Twice the timeout leaves a loaded machine room; one by one it would take six.
  EXPECT_LT(joined_after, 2 * kHelloTimeout)
      << "admitted after " << std::chrono::duration<double>(joined_after).count() << " s";
  ASSERT_TRUE(testing::wait_until([&] { return hub->link(0)->adopt(); }));

  // Each silent connection is refused for its silence, not before its own
  // deadline, and all of them about together (not one timeout after another).
  for (auto& s : silent) {
    Message m;
    ASSERT_EQ(s.channel.receive(m, 10 * kHelloTimeoutMs), RecvStatus::kOk);
    const auto waited = Clock::now() - s.opened;
    EXPECT_EQ(m.type(), MsgType::kReject);
    EXPECT_EQ(m.extra_text(), "expected a hello message within 1000 ms");
    // (Less a little: the hub may accept it just before our clock reads `opened`.)
    EXPECT_GE(waited, kHelloTimeout - milliseconds(5));
    EXPECT_LT(waited, 3 * kHelloTimeout);
  }
  EXPECT_EQ(hub->rejected(), static_cast<std::uint64_t>(kSilent));
}

TEST(ExternalHelloWait, BeyondTheLimitTheConnectionWaitingLongestIsRefused) {
  SocketPath path;
  constexpr int kHelloTimeoutMs = 30000;  // far beyond the test: only the limit refuses
  const auto hub = make_external_hub(hub_settings(path.str(), kHelloTimeoutMs), one_node());
  std::vector<MessageChannel> silent;
  for (std::size_t i = 0; i <= kMaxWaitingHellos; ++i) {
    silent.push_back(MessageChannel::connect_to(path.str()));
  }
  Message m;
  ASSERT_EQ(silent.front().receive(m, 10000), RecvStatus::kOk);
  EXPECT_EQ(m.type(), MsgType::kReject);
  EXPECT_EQ(m.extra_text(),
            "more than 64 connections waiting to say hello; this one waited longest");
  EXPECT_EQ(silent[1].receive(m, 0), RecvStatus::kTimeout) << "the others keep waiting";
  // A good hello still gets in at once, although the waiting room is full.
  ExternalClient good({path.str(), kNode, "samples", "unit-test", 10000});
  EXPECT_NO_THROW(good.connect());
}

}  // namespace
}  // namespace rfsitl::external
