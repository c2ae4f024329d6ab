#include "rfsitl/external/external_hub.hpp"

#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "external_test_support.hpp"
#include "rfsitl/external/client/external_client.hpp"
#include "rfsitl/external/phy_config_json.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::external {
namespace {

using testing::SocketPath;
using testing::wait_until;

constexpr NodeId kSamplesNode = 3;
constexpr NodeId kTransceiverNode = 4;

/// Node 3 (engine index 0) runs the samples role, node 4 (index 1) a DSSS PHY
/// in the transceiver role: settings far from the defaults, so that a welcome
/// that carried the defaults instead would be noticed.
scenario::PhyChoice transceiver_phy() {
  return scenario::PhyChoice::of("dsss")
      .with("code", std::string("gold31:3"))
      .with("modulation", std::string("dqpsk"))
      .with("samples_per_chip", 2U)
      .with("max_payload_bytes", 321U);
}

HubSettings hub_settings(const std::string& path, int reply_timeout_ms = 1000) {
  HubSettings s;
  s.socket_path = path;
  s.reply_timeout_ms = reply_timeout_ms;
  s.sample_rate_hz = 2.5e6;
  s.tick_samples = 320;
  s.virtual_time = true;
  return s;
}

std::vector<ExternalNodeSpec> two_nodes() {
  return {ExternalNodeSpec{0, kSamplesNode, Role::kSamples, ""},
          ExternalNodeSpec{1, kTransceiverNode, Role::kTransceiver,
                           phy_to_json("dsss", transceiver_phy().settings)}};
}

ExternalClient::Settings client_settings(const std::string& path, NodeId id,
                                         const std::string& role) {
  ExternalClient::Settings s;
  s.socket_path = path;
  s.node_id = id;
  s.role = role;
  s.program = "unit-test";
  s.handshake_timeout_ms = 3000;
  return s;
}

/// The message of the std::runtime_error that connect() throws ("" if none).
std::string connect_error(ExternalClient& client) {
  try {
    client.connect();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

MsgHeader header_of(MsgType type, std::uint64_t tick) {
  MsgHeader h;
  h.type = static_cast<std::uint16_t>(type);
  h.tick = tick;
  return h;
}

TEST(ExternalHub, SamplesClientJoinsAndItsWelcomeCarriesTheRunTiming) {
  SocketPath path;
  const HubSettings hs = hub_settings(path.str());
  const auto hub = make_external_hub(hs, two_nodes());
  EXPECT_EQ(hub->socket_path(), path.str());

  ExternalClient client(client_settings(path.str(), kSamplesNode, "samples"));
  const Welcome& w = client.connect();
  EXPECT_TRUE(client.connected());
  EXPECT_EQ(w.node_id, kSamplesNode);
  EXPECT_EQ(w.sample_rate_hz, hs.sample_rate_hz);
  EXPECT_EQ(w.tick_samples, hs.tick_samples);
  EXPECT_TRUE(w.virtual_time);
  EXPECT_TRUE(w.phy_json.empty()) << "the samples role runs no PHY of ours: " << w.phy_json;
  EXPECT_EQ(hub->rejected(), 0U);

  const auto link = hub->link(0);
  ASSERT_NE(link, nullptr);
  EXPECT_EQ(link->id(), kSamplesNode);
  ASSERT_TRUE(wait_until([&] { return link->adopt(); }));
  EXPECT_TRUE(link->connected());
  EXPECT_EQ(link->joins(), 1U);
}

TEST(ExternalHub, TransceiverClientsWelcomeCarriesItsPhySettings) {
  SocketPath path;
  HubSettings hs = hub_settings(path.str());
  hs.virtual_time = false;
  const auto hub = make_external_hub(hs, two_nodes());

  ExternalClient client(client_settings(path.str(), kTransceiverNode, "transceiver"));
  const Welcome& w = client.connect();
  EXPECT_EQ(w.node_id, kTransceiverNode);
  EXPECT_EQ(w.sample_rate_hz, hs.sample_rate_hz);
  EXPECT_EQ(w.tick_samples, hs.tick_samples);
  EXPECT_FALSE(w.virtual_time);
  const scenario::PhyChoice expected = transceiver_phy();
  const PhyRequest got = phy_from_json(w.phy_json);
  EXPECT_EQ(got.type, expected.type);
  EXPECT_EQ(got.settings.get<std::string>("code"), "gold31:3");
  EXPECT_EQ(got.settings.get<std::string>("modulation"), "dqpsk");
  EXPECT_EQ(got.settings.get<std::uint64_t>("samples_per_chip"), 2U);
  EXPECT_EQ(got.settings.get<std::uint64_t>("max_payload_bytes"), 321U);
  EXPECT_EQ(got.settings, expected.settings);
}

TEST(ExternalHub, HubHasLinksOnlyForExternalNodes) {
  SocketPath path;
  const auto hub = make_external_hub(hub_settings(path.str()), two_nodes());
  ASSERT_NE(hub->link(0), nullptr);
  ASSERT_NE(hub->link(1), nullptr);
  EXPECT_EQ(hub->link(0)->id(), kSamplesNode);
  EXPECT_EQ(hub->link(1)->id(), kTransceiverNode);
  EXPECT_EQ(hub->link(2), nullptr);
}

TEST(ExternalHub, UnknownNodeIsRejectedWithAReasonNamingIt) {
  SocketPath path;
  const auto hub = make_external_hub(hub_settings(path.str()), two_nodes());
  ExternalClient client(client_settings(path.str(), 9, "samples"));
  const std::string error = connect_error(client);
  ASSERT_FALSE(error.empty()) << "node 9 was admitted";
  EXPECT_TRUE(contains(error, "node 9")) << error;
  EXPECT_TRUE(contains(error, "not an external node")) << error;
  EXPECT_TRUE(contains(error, "3, 4")) << "should list the external nodes: " << error;
  EXPECT_TRUE(contains(error, path.str())) << error;
  EXPECT_FALSE(client.connected());
  EXPECT_EQ(hub->rejected(), 1U);
  EXPECT_EQ(hub->never_joined(), (std::vector<NodeId>{kSamplesNode, kTransceiverNode}));
}

TEST(ExternalHub, WrongRoleIsRejectedWithAReasonNamingBothRoles) {
  SocketPath path;
  const auto hub = make_external_hub(hub_settings(path.str()), two_nodes());

  ExternalClient as_transceiver(client_settings(path.str(), kSamplesNode, "transceiver"));
  std::string error = connect_error(as_transceiver);
  ASSERT_FALSE(error.empty()) << "node 3 was admitted in the wrong role";
  EXPECT_TRUE(contains(error, "node 3")) << error;
  EXPECT_TRUE(contains(error, "'samples'")) << error;
  EXPECT_TRUE(contains(error, "'transceiver'")) << error;
  EXPECT_EQ(hub->rejected(), 1U);

  ExternalClient as_samples(client_settings(path.str(), kTransceiverNode, "samples"));
  error = connect_error(as_samples);
  ASSERT_FALSE(error.empty()) << "node 4 was admitted in the wrong role";
  EXPECT_TRUE(contains(error, "node 4")) << error;
  EXPECT_TRUE(contains(error, "expects role 'transceiver'")) << error;
  EXPECT_EQ(hub->rejected(), 2U);

  // A refused hello is not a join.
  EXPECT_EQ(hub->never_joined(), (std::vector<NodeId>{kSamplesNode, kTransceiverNode}));
  EXPECT_FALSE(hub->link(0)->adopt());
  EXPECT_FALSE(hub->link(1)->adopt());
}

TEST(ExternalHub, ConnectionThatSendsSomethingElseThanAHelloIsRejected) {
  SocketPath path;
  const auto hub = make_external_hub(hub_settings(path.str()), two_nodes());
  MessageChannel raw = MessageChannel::connect_to(path.str());
  ASSERT_TRUE(raw.send(header_of(MsgType::kTx, 0)));
  Message m;
  ASSERT_EQ(raw.receive(m, 3000), RecvStatus::kOk);
  EXPECT_EQ(m.type(), MsgType::kReject);
  EXPECT_TRUE(contains(m.extra_text(), "hello")) << m.extra_text();
  EXPECT_EQ(raw.receive(m, 3000), RecvStatus::kClosed);
  EXPECT_EQ(hub->rejected(), 1U);
}

TEST(ExternalHub, HelloWithBadJsonIsRejected) {
  SocketPath path;
  const auto hub = make_external_hub(hub_settings(path.str()), two_nodes());
  MessageChannel raw = MessageChannel::connect_to(path.str());
  const std::string text = R"({"role": "samples"})";  // no node_id
  ASSERT_TRUE(raw.send(header_of(MsgType::kHello, 0), {},
                       {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()}));
  Message m;
  ASSERT_EQ(raw.receive(m, 3000), RecvStatus::kOk);
  EXPECT_EQ(m.type(), MsgType::kReject);
  EXPECT_TRUE(contains(m.extra_text(), "bad hello JSON")) << m.extra_text();
  EXPECT_EQ(hub->rejected(), 1U);
  EXPECT_EQ(hub->never_joined().size(), 2U);
}

TEST(ExternalHub, NeverJoinedListsNodesUntilTheyConnect) {
  SocketPath path;
  const auto hub = make_external_hub(hub_settings(path.str()), two_nodes());
  EXPECT_EQ(hub->never_joined(), (std::vector<NodeId>{kSamplesNode, kTransceiverNode}));

  ExternalClient t(client_settings(path.str(), kTransceiverNode, "transceiver"));
  t.connect();
  // The hub offers the connection just after sending the welcome.
  EXPECT_TRUE(wait_until([&] { return hub->never_joined() == std::vector<NodeId>{kSamplesNode}; }))
      << "node 4 still listed after connecting";

  ExternalClient s(client_settings(path.str(), kSamplesNode, "samples"));
  s.connect();
  EXPECT_TRUE(wait_until([&] { return hub->never_joined().empty(); }));

  // Once joined is joined, even after the connection is dropped.
  const auto link = hub->link(0);
  ASSERT_TRUE(link->adopt());
  link->drop("test");
  EXPECT_TRUE(hub->never_joined().empty());
}

TEST(ExternalHub, SecondEmulatorCannotBindASocketPathInUseByALiveHub) {
  SocketPath path;
  const auto hub = make_external_hub(hub_settings(path.str()), two_nodes());
  try {
    make_external_hub(hub_settings(path.str()), two_nodes());
    FAIL() << "a second hub bound a socket path in use";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(contains(e.what(), "in use")) << e.what();
    EXPECT_TRUE(contains(e.what(), path.str())) << e.what();
  }
  // The failed attempt left the live hub's socket alone: nodes still join it.
  ExternalClient client(client_settings(path.str(), kSamplesNode, "samples"));
  EXPECT_NO_THROW(client.connect());
  EXPECT_TRUE(wait_until([&] { return hub->link(0)->adopt(); }));
}

TEST(ExternalHub, StaleSocketFileOfADeadEmulatorIsReplaced) {
  SocketPath path;
  {
    // A socket file that nobody accepts on, as a crashed emulator leaves it.
    const int fd = ::socket(AF_UNIX, SOCK_SEQPACKET, 0);
    ASSERT_GE(fd, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::memcpy(addr.sun_path, path.str().c_str(), path.str().size() + 1);
    ASSERT_EQ(::bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr), 0);
    ::close(fd);
  }
  struct stat st {};
  ASSERT_EQ(::stat(path.str().c_str(), &st), 0);
  ASSERT_TRUE(S_ISSOCK(st.st_mode));

  std::unique_ptr<ExternalHub> hub;
  ASSERT_NO_THROW(hub = make_external_hub(hub_settings(path.str()), two_nodes()));
  ASSERT_EQ(::stat(path.str().c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600U) << "socket should be private to the user";
  ExternalClient client(client_settings(path.str(), kSamplesNode, "samples"));
  EXPECT_NO_THROW(client.connect());
  EXPECT_TRUE(wait_until([&] { return hub->link(0)->adopt(); }));
}

TEST(ExternalHub, HubRemovesItsSocketFileWhenDestroyed) {
  SocketPath path;
  auto hub = make_external_hub(hub_settings(path.str()), two_nodes());
  struct stat st {};
  ASSERT_EQ(::stat(path.str().c_str(), &st), 0);
  hub.reset();
  EXPECT_NE(::stat(path.str().c_str(), &st), 0);
}

TEST(ExternalHub, SocketPathTooLongForSunPathIsRefusedNamingIt) {
  const std::string path = "/tmp/" + std::string(200, 'x') + ".sock";
  try {
    make_external_hub(hub_settings(path), two_nodes());
    FAIL() << "a hub bound an impossible path";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(contains(e.what(), path)) << e.what();
  }
}

TEST(ExternalNodeLink, CallReturnsTheReplyForTheSameTick) {
  SocketPath path;
  const auto hub = make_external_hub(hub_settings(path.str()), two_nodes());
  ExternalClient client(client_settings(path.str(), kSamplesNode, "samples"));
  client.connect();
  const auto link = hub->link(0);
  ASSERT_TRUE(wait_until([&] { return link->adopt(); }));

  // The socket keeps the client's answer until the link reads it, so the reply
  // can be sent first and no second thread is needed.
  const std::vector<cf32> answer = {{1.0F, 2.0F}, {3.0F, 4.0F}};
  ASSERT_TRUE(client.channel().send(header_of(MsgType::kTx, 42), answer));
  const std::vector<cf32> request = {{5.0F, 6.0F}};
  const Message* reply = link->call(header_of(MsgType::kTick, 42), request, {}, MsgType::kTx);
  ASSERT_NE(reply, nullptr);
  EXPECT_EQ(reply->header.tick, 42U);
  EXPECT_EQ(reply->samples, answer);
  EXPECT_TRUE(link->connected());
  EXPECT_EQ(link->drops(), 0U);

  ASSERT_EQ(client.wait_tick(1000), RecvStatus::kOk);
  EXPECT_EQ(client.tick().index, 42U);
  ASSERT_EQ(client.tick().rx.size(), 1U);
  EXPECT_EQ(client.tick().rx[0], request[0]);
}

TEST(ExternalNodeLink, ReplyForAnotherTickOrOfAnotherTypeDropsTheLink) {
  SocketPath path;
  const auto hub = make_external_hub(hub_settings(path.str()), two_nodes());
  const auto link = hub->link(0);
  ExternalClient client(client_settings(path.str(), kSamplesNode, "samples"));

  client.connect();
  ASSERT_TRUE(wait_until([&] { return link->adopt(); }));
  ASSERT_TRUE(client.channel().send(header_of(MsgType::kTx, 6)));  // one tick late
  EXPECT_EQ(link->call(header_of(MsgType::kTick, 7), {}, {}, MsgType::kTx), nullptr);
  EXPECT_FALSE(link->connected());
  EXPECT_EQ(link->drops(), 1U);

  client.connect();
  ASSERT_TRUE(wait_until([&] { return link->adopt(); }));
  ASSERT_TRUE(client.channel().send(header_of(MsgType::kRxResult, 8)));  // wrong type
  EXPECT_EQ(link->call(header_of(MsgType::kTick, 8), {}, {}, MsgType::kTx), nullptr);
  EXPECT_FALSE(link->connected());
  EXPECT_EQ(link->drops(), 2U);
  EXPECT_EQ(link->timeouts(), 0U);
  EXPECT_EQ(link->joins(), 2U);
}

TEST(ExternalNodeLink, ClientThatNeverAnswersIsDroppedAfterTheReplyTimeoutAndMayRejoin) {
  SocketPath path;
  constexpr int kReplyTimeoutMs = 150;
  const auto hub = make_external_hub(hub_settings(path.str(), kReplyTimeoutMs), two_nodes());
  const auto link = hub->link(0);
  ExternalClient client(client_settings(path.str(), kSamplesNode, "samples"));
  client.connect();
  ASSERT_TRUE(wait_until([&] { return link->adopt(); }));
  ASSERT_TRUE(link->connected());
  EXPECT_EQ(link->joins(), 1U);

  const auto t0 = std::chrono::steady_clock::now();
  const Message* reply = link->call(header_of(MsgType::kTick, 5), {}, {}, MsgType::kTx);
  const auto waited = std::chrono::steady_clock::now() - t0;
  EXPECT_EQ(reply, nullptr);
  EXPECT_GE(waited, std::chrono::milliseconds(kReplyTimeoutMs - 5));
  EXPECT_LT(waited, std::chrono::seconds(3));
  EXPECT_FALSE(link->connected());
  EXPECT_EQ(link->timeouts(), 1U);
  EXPECT_EQ(link->drops(), 1U);

  // The client still gets the tick it never answered, then sees the drop.
  ASSERT_EQ(client.wait_tick(1000), RecvStatus::kOk);
  EXPECT_EQ(client.tick().index, 5U);
  EXPECT_EQ(client.wait_tick(1000), RecvStatus::kClosed);

  // Rejoin: the same client connects again and the link adopts it.
  client.connect();
  ASSERT_TRUE(wait_until([&] { return link->adopt(); }));
  EXPECT_TRUE(link->connected());
  EXPECT_EQ(link->joins(), 2U);
  EXPECT_EQ(link->drops(), 1U);

  // And it works again.
  ASSERT_TRUE(client.channel().send(header_of(MsgType::kTx, 6)));
  EXPECT_NE(link->call(header_of(MsgType::kTick, 6), {}, {}, MsgType::kTx), nullptr);
  EXPECT_EQ(link->timeouts(), 1U);
}

TEST(ExternalNodeLink, CallOnALinkWithoutConnectionFailsAndCountsADrop) {
  NodeLink link(7, 100);
  EXPECT_FALSE(link.connected());
  EXPECT_FALSE(link.adopt());
  EXPECT_EQ(link.call(header_of(MsgType::kTick, 0), {}, {}, MsgType::kTx), nullptr);
  EXPECT_EQ(link.drops(), 1U);
  EXPECT_EQ(link.timeouts(), 0U);
}

TEST(ExternalNodeLink, NewerOfferReplacesOneNotYetAdopted) {
  SocketPath path;
  const auto hub = make_external_hub(hub_settings(path.str()), two_nodes());
  const auto link = hub->link(0);
  ExternalClient first(client_settings(path.str(), kSamplesNode, "samples"));
  first.connect();
  ASSERT_TRUE(
      wait_until([&] { return hub->never_joined() == std::vector<NodeId>{kTransceiverNode}; }));
  ExternalClient second(client_settings(path.str(), kSamplesNode, "samples"));
  second.connect();
  // The first connection is closed once the hub has replaced its offer.
  Message m;
  EXPECT_EQ(first.channel().receive(m, 3000), RecvStatus::kClosed);
  ASSERT_TRUE(link->adopt());
  EXPECT_FALSE(link->adopt()) << "only one connection was waiting";
  EXPECT_EQ(link->joins(), 1U);

  // The adopted connection is the second client's.
  ASSERT_TRUE(second.channel().send(header_of(MsgType::kTx, 1)));
  EXPECT_NE(link->call(header_of(MsgType::kTick, 1), {}, {}, MsgType::kTx), nullptr);
}

}  // namespace
}  // namespace rfsitl::external
