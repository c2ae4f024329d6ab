/// Every end of an external node's connection is counted as a drop, also when
/// no round trip was in flight: an idle `rfsitl node` that dies, or one whose
/// node is taken over by a new connection before the old one was noticed gone.
/// joins - drops is then always the number of live connections (0 or 1).
#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "external_test_support.hpp"
#include "rfsitl/external/client/external_client.hpp"
#include "rfsitl/external/external_hub.hpp"
#include "rfsitl/external/external_transceivers.hpp"
#include "rfsitl/external/phy_config_json.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::external {
namespace {

using testing::SocketPath;
using testing::wait_until;

constexpr NodeId kNode = 5;
constexpr std::uint32_t kB = 250;

/// A hub with one transceiver-role node (GMSK) and the engine's proxy for it.
struct IdleNode {
  SocketPath path;
  scenario::PhyChoice phy;
  std::unique_ptr<ExternalHub> hub;
  std::shared_ptr<NodeLink> link;
  std::unique_ptr<phy::Transceiver> proxy;
  std::uint64_t tick = 0;

  IdleNode() {
    HubSettings hs;
    hs.socket_path = path.str();
    hs.tick_samples = kB;
    hub = make_external_hub(
        hs, {ExternalNodeSpec{0, kNode, Role::kTransceiver, phy_to_json(phy.type, phy.settings)}});
    link = hub->link(0);
    proxy = make_remote_transceiver(link, phy);
  }

  ExternalClient::Settings client() const {
    return ExternalClient::Settings{path.str(), kNode, "transceiver", "unit-test", 3000};
  }

  /// The engine's start of one tick for an idle node: begin_tick, nothing to
  /// send (no frame queued), nothing heard. Returns joins - drops.
  std::int64_t idle_tick() {
    proxy->begin_tick(tick, static_cast<SampleTime>(tick * kB));
    ++tick;
    return static_cast<std::int64_t>(link->joins()) - static_cast<std::int64_t>(link->drops());
  }

  /// Ticks until the offered connection is adopted (a few ms: the hub offers
  /// it right after the welcome).
  bool tick_until_joined() {
    const std::uint64_t before = link->joins();
    return wait_until([&] {
      idle_tick();
      return link->joins() > before;
    });
  }
};

TEST(ExternalLinkDrops, IdleProcessThatDiesIsCountedAsADropWithoutAnyRoundTrip) {
  IdleNode n;
  ExternalClient process(n.client());
  process.connect();
  ASSERT_TRUE(n.tick_until_joined());
  ASSERT_TRUE(n.link->connected());
  EXPECT_FALSE(n.proxy->tx_busy()) << "a joined idle node can start a frame";

  // Healthy and idle: many ticks, no drop.
  for (std::uint32_t i = 0; i < 4 * NodeLink::kPeerCheckEvery; ++i) {
    ASSERT_EQ(n.idle_tick(), 1);
  }
  EXPECT_TRUE(n.link->connected());

  process.disconnect();  // as the kernel does for a process killed with SIGKILL
  for (std::uint32_t i = 0; i < NodeLink::kPeerCheckEvery && n.link->connected(); ++i) {
    n.idle_tick();
  }
  EXPECT_FALSE(n.link->connected())
      << "the closed socket was not noticed within " << NodeLink::kPeerCheckEvery << " idle ticks";
  EXPECT_EQ(n.link->drops(), 1U);
  EXPECT_EQ(n.link->timeouts(), 0U);
  EXPECT_EQ(n.idle_tick(), 0) << "joins - drops must be 0 with no process connected";
  EXPECT_TRUE(n.proxy->tx_busy()) << "while the process is away nothing may be started";

  // More idle ticks do not count the same drop again.
  for (std::uint32_t i = 0; i < 4 * NodeLink::kPeerCheckEvery; ++i) n.idle_tick();
  EXPECT_EQ(n.link->drops(), 1U);

  // The restarted process rejoins: the books balance again.
  ExternalClient restarted(n.client());
  restarted.connect();
  ASSERT_TRUE(n.tick_until_joined());
  EXPECT_EQ(n.link->joins(), 2U);
  EXPECT_EQ(n.idle_tick(), 1);
}

TEST(ExternalLinkDrops, RejoinWhileTheOldConnectionStillLooksUpCountsTheOldOneAsDropped) {
  IdleNode n;
  ExternalClient first(n.client());
  first.connect();
  ASSERT_TRUE(n.tick_until_joined());

  // A second process joins as the same node before any check saw the first
  // one go (here the first is even still alive): adopting the new connection
  // ends the old one, and that is a drop.
  ExternalClient second(n.client());
  second.connect();
  ASSERT_TRUE(wait_until([&] { return n.link->adopt(); }));
  EXPECT_EQ(n.link->joins(), 2U);
  EXPECT_EQ(n.link->drops(), 1U);
  EXPECT_TRUE(n.link->connected());
  EXPECT_EQ(n.idle_tick(), 1);

  // The old process sees its connection closed; the new one carries the node.
  Message m;
  EXPECT_EQ(first.channel().receive(m, 3000), RecvStatus::kClosed);
  MsgHeader tx;
  tx.type = static_cast<std::uint16_t>(MsgType::kTx);
  tx.tick = 77;
  ASSERT_TRUE(second.channel().send(tx));
  MsgHeader request;
  request.type = static_cast<std::uint16_t>(MsgType::kTxRequest);
  request.tick = 77;
  EXPECT_NE(n.link->call(request, {}, {}, MsgType::kTx), nullptr);
  EXPECT_EQ(n.link->drops(), 1U);
}

TEST(ExternalLinkDrops, PendingDataOnAnIdleLinkIsLeftForTheNextRoundTrip) {
  IdleNode n;
  ExternalClient process(n.client());
  process.connect();
  ASSERT_TRUE(n.tick_until_joined());
  // A reply sent early (the test's stand-in for one that arrives before the
  // request) is readable between round trips; the idle check must not judge it.
  MsgHeader tx;
  tx.type = static_cast<std::uint16_t>(MsgType::kTx);
  tx.tick = 3;
  ASSERT_TRUE(process.channel().send(tx));
  for (std::uint32_t i = 0; i < 2 * NodeLink::kPeerCheckEvery; ++i) ASSERT_EQ(n.idle_tick(), 1);
  MsgHeader request;
  request.type = static_cast<std::uint16_t>(MsgType::kTxRequest);
  request.tick = 3;
  EXPECT_NE(n.link->call(request, {}, {}, MsgType::kTx), nullptr);
  EXPECT_EQ(n.link->drops(), 0U);
}

TEST(ExternalLinkDrops, WatchOnALinkWithoutConnectionCountsNothing) {
  NodeLink link(kNode, 100);
  for (std::uint32_t i = 0; i < 2 * NodeLink::kPeerCheckEvery; ++i) {
    EXPECT_FALSE(link.watch_peer());
  }
  EXPECT_EQ(link.drops(), 0U);
  EXPECT_EQ(link.joins(), 0U);
}

}  // namespace
}  // namespace rfsitl::external
