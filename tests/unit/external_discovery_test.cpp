/// Discovery (kDiscover / kDiscovery, wire_protocol.hpp): a program asks which
/// external nodes an emulator has without claiming any. Its JSON is checked
/// like the welcome's, a bad request is refused and counted like a bad hello,
/// and the hello/welcome of older clients is unchanged.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "external_test_support.hpp"
#include "log_capture.hpp"
#include "rfsitl/external/client/external_client.hpp"
#include "rfsitl/external/client/handshake.hpp"
#include "rfsitl/external/client/message_channel.hpp"
#include "rfsitl/external/external_hub.hpp"

namespace rfsitl::external {
namespace {

using ::rfsitl::testing::LogCapture;
using testing::SocketPath;

DiscoveredNode sample_node() {
  return {7, "swarm node 7", "samples", 2e6, 500, 915e6, false, true};
}

std::string read_error(const std::string& text) {
  try {
    read_discovery(text);
  } catch (const HandshakeError& e) {
    return e.what();
  }
  return "";
}

TEST(ExternalDiscovery, AnswerReadsBackAsWritten) {
  const auto nodes = read_discovery(discovery_json({sample_node()}));
  ASSERT_EQ(nodes.size(), 1U);
  const DiscoveredNode& n = nodes[0];
  EXPECT_EQ(n.node_id, 7);
  EXPECT_EQ(n.label, "swarm node 7");
  EXPECT_EQ(n.role, "samples");
  EXPECT_EQ(n.sample_rate_hz, 2e6);
  EXPECT_EQ(n.tick_samples, 500U);
  EXPECT_EQ(n.carrier_hz, 915e6);
  EXPECT_FALSE(n.virtual_time);
  EXPECT_TRUE(n.claimed);
  EXPECT_TRUE(read_discovery(discovery_json({})).empty());
}

TEST(ExternalDiscovery, RequestReadsBackAndChecksItsVersion) {
  EXPECT_EQ(read_discovery_request(discovery_request_json({"soapy find"})).program, "soapy find");
  EXPECT_THROW(read_discovery_request(R"({"discovery": 2})"), HandshakeError);
  EXPECT_THROW(read_discovery_request(R"({"program": "x"})"), HandshakeError);
  EXPECT_THROW(read_discovery_request("[1]"), HandshakeError);
}

TEST(ExternalDiscovery, AnswerFieldsAreCheckedLikeTheWelcome) {
  const std::string ok = R"("label": "a", "role": "samples", "sample_rate_hz": 1e6,
      "tick_samples": 250, "carrier_hz": 2.4e9, "time_mode": "realtime", "claimed": false)";
  EXPECT_EQ(read_error(R"({"discovery": 1, "nodes": [{"node_id": 3, )" + ok + "}]}"), "");
  EXPECT_EQ(read_error(R"({"discovery": 2, "nodes": []})"), "discovery 2, this program speaks 1");
  EXPECT_EQ(read_error(R"({"discovery": 1, "nodes": {}})"), "nodes: expected a JSON array, got {}");
  EXPECT_EQ(read_error(R"({"discovery": 1, "nodes": [{"node_id": 4294967298, )" + ok + "}]}"),
            "node_id 4294967298 out of range 1..254");
  EXPECT_EQ(read_error(R"({"discovery": 1, "nodes": [{"node_id": 3, "claimed": 1, )" +
                       ok.substr(0, ok.find(", \"claimed\"")) + "}]}"),
            "claimed: expected true or false, got 1");
  EXPECT_EQ(read_error(R"({"discovery": 1, "nodes": [{"node_id": 3, "carrier_hz": -1, )" +
                       std::string(R"("label": "a", "role": "samples", "sample_rate_hz": 1e6,
      "tick_samples": 250, "time_mode": "realtime", "claimed": false}]})")),
            "carrier_hz: expected a finite number > 0, got -1");
  EXPECT_EQ(read_error("{\"discovery\": 1, \"nodes\": [3]}"), "nodes: expected objects, got 3");
  EXPECT_EQ(read_error("{\"discovery\": 1,"), "not JSON (syntax error at byte 17)");
}

class HubDiscovery : public ::testing::Test {
 protected:
  void SetUp() override {
    HubSettings hs;
    hs.socket_path = path.str();
    hs.sample_rate_hz = 2e6;
    hs.tick_samples = 400;
    hs.carrier_hz = 868e6;
    hs.scenario_name = "test";
    hub = make_external_hub(hs, {ExternalNodeSpec{0, 2, Role::kSamples, ""},
                                 ExternalNodeSpec{1, 5, Role::kTransceiver, "{}"}});
  }

  /// Sends one kDiscover with `extra` and returns the answer.
  Message ask(const std::string& extra) {
    MessageChannel ch = MessageChannel::connect_to(path.str());
    MsgHeader h;
    h.type = static_cast<std::uint16_t>(MsgType::kDiscover);
    EXPECT_TRUE(
        ch.send(h, {}, {reinterpret_cast<const std::uint8_t*>(extra.data()), extra.size()}));
    Message m;
    EXPECT_EQ(ch.receive(m, 5000), RecvStatus::kOk);
    return m;
  }

  SocketPath path;
  std::unique_ptr<ExternalHub> hub;
};

TEST_F(HubDiscovery, ListsEveryExternalNodeAndClaimsNone) {
  for (int round = 0; round < 3; ++round) {
    const auto nodes = discover(path.str(), 5000, "unit test");
    ASSERT_EQ(nodes.size(), 2U);
    EXPECT_EQ(nodes[0].node_id, 2);
    EXPECT_EQ(nodes[0].label, "test node 2");
    EXPECT_EQ(nodes[0].role, "samples");
    EXPECT_EQ(nodes[0].sample_rate_hz, 2e6);
    EXPECT_EQ(nodes[0].tick_samples, 400U);
    EXPECT_EQ(nodes[0].carrier_hz, 868e6);
    EXPECT_FALSE(nodes[0].claimed);
    EXPECT_EQ(nodes[1].node_id, 5);
    EXPECT_EQ(nodes[1].role, "transceiver");
  }
  // Asking is not joining: the nodes still wait, nothing was refused.
  EXPECT_EQ(hub->never_joined(), (std::vector<NodeId>{2, 5}));
  EXPECT_EQ(hub->rejected(), 0U);
  EXPECT_FALSE(hub->link(0)->claimed());
}

TEST_F(HubDiscovery, ShowsANodeClaimedOnceAProgramSaidHello) {
  // An older client's hello, unchanged: welcomed with protocol 1.
  ExternalClient client({path.str(), 2, "samples", "old client", 5000});
  EXPECT_EQ(client.connect().tick_samples, 400U);
  const auto link = hub->link(0);
  // Offered, not yet adopted by an engine: claimed already.
  ASSERT_TRUE(testing::wait_until([&] { return link->claimed(); }));
  EXPECT_TRUE(discover(path.str(), 5000)[0].claimed);
  ASSERT_TRUE(link->adopt());
  EXPECT_TRUE(discover(path.str(), 5000)[0].claimed);
  link->drop("test");
  EXPECT_FALSE(discover(path.str(), 5000)[0].claimed);
}

TEST_F(HubDiscovery, RefusesABadRequestClearlyAndCountsIt) {
  LogCapture log;
  const Message garbled = ask("{\"discovery\": ");
  EXPECT_EQ(garbled.type(), MsgType::kReject);
  EXPECT_EQ(garbled.extra_text(), "bad discovery request JSON: not JSON (syntax error at byte 15)");
  const Message future = ask(R"({"discovery": 9})");
  EXPECT_EQ(future.type(), MsgType::kReject);
  EXPECT_EQ(future.extra_text(), "bad discovery request JSON: discovery 9, this program speaks 1");
  EXPECT_EQ(hub->rejected(), 2U);
  EXPECT_EQ(log.lines_with("refused a connection").size(), 2U);
  // The hub answers the next, good request as before.
  EXPECT_EQ(discover(path.str(), 5000).size(), 2U);
}

TEST(ExternalDiscoveryClient, NamesTheSocketWhenNoEmulatorListens) {
  SocketPath path;
  try {
    discover(path.str(), 1000);
    FAIL() << "discover() returned without an emulator";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path.str()), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rfsitl::external
