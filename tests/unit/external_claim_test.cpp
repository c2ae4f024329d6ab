/// Exclusive claims (Hello::exclusive): the hub refuses an exclusive hello for
/// a node another process holds, also when two arrive at the same instant,
/// while a plain hello still takes the node over (how a restarted process
/// rejoins, and the SoapySDR module's takeover=1).
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "external_test_support.hpp"
#include "rfsitl/external/client/external_client.hpp"
#include "rfsitl/external/client/handshake.hpp"
#include "rfsitl/external/external_hub.hpp"

namespace rfsitl::external {
namespace {

using testing::SocketPath;
using testing::wait_until;

constexpr NodeId kNode = 7;

struct Fixture {
  SocketPath path;
  std::unique_ptr<ExternalHub> hub;

  Fixture() {
    HubSettings hs;
    hs.socket_path = path.str();
    hs.tick_samples = 64;
    hub = make_external_hub(hs, {ExternalNodeSpec{0, kNode, Role::kSamples, ""}});
  }

  ExternalClient client(bool exclusive) const {
    return ExternalClient({path.str(), kNode, "samples", "unit-test", 3000, exclusive});
  }
};

TEST(ExternalClaim, ExclusiveIsSentOnlyWhenAskedAndReadBack) {
  const std::string plain = hello_json({kNode, "samples", "p"});
  EXPECT_EQ(plain.find("exclusive"), std::string::npos) << "older emulators see the old hello";
  EXPECT_FALSE(read_hello(plain).exclusive);
  EXPECT_TRUE(read_hello(hello_json({kNode, "samples", "p", true})).exclusive);
  EXPECT_THROW(read_hello(R"({"node_id":7,"role":"samples","exclusive":1})"), HandshakeError);
}

TEST(ExternalClaim, SecondExclusiveClaimIsRefusedAndATakeoverStillWorks) {
  Fixture f;
  ExternalClient first = f.client(true);
  first.connect();
  ASSERT_TRUE(wait_until([&] { return f.hub->link(0)->claimed(); }));

  ExternalClient second = f.client(true);
  try {
    second.connect();
    FAIL() << "a second exclusive claim was admitted";
  } catch (const ConnectRejected& e) {
    EXPECT_NE(e.reason().find("node 7 is already claimed by another program"), std::string::npos)
        << e.reason();
  }
  EXPECT_EQ(f.hub->rejected(), 1U);

  ExternalClient takeover = f.client(false);
  EXPECT_NO_THROW(takeover.connect()) << "a plain hello takes the node over";
}

TEST(ExternalClaim, OfTwoExclusiveHellosAtTheSameInstantOneIsRefused) {
  Fixture f;
  // Both connections and both hellos are in the hub's socket before it reads
  // either: only its order of admission decides.
  std::vector<MessageChannel> channels;
  for (int i = 0; i < 2; ++i) channels.push_back(MessageChannel::connect_to(f.path.str()));
  const std::string text = hello_json({kNode, "samples", "racer", true});
  MsgHeader h;
  h.type = static_cast<std::uint16_t>(MsgType::kHello);
  for (auto& ch : channels) {
    ASSERT_TRUE(ch.send(h, {}, {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()}));
  }
  int welcomes = 0, rejects = 0;
  for (auto& ch : channels) {
    Message answer;
    ASSERT_EQ(ch.receive(answer, 3000), RecvStatus::kOk);
    welcomes += answer.type() == MsgType::kWelcome;
    rejects += answer.type() == MsgType::kReject;
  }
  EXPECT_EQ(welcomes, 1);
  EXPECT_EQ(rejects, 1);
}

TEST(ExternalClaim, AClaimWhoseProcessHungUpBeforeItWasAdoptedHoldsNothing) {
  Fixture f;
  {
    ExternalClient gone = f.client(true);
    gone.connect();
    ASSERT_TRUE(wait_until([&] { return f.hub->link(0)->claimed(); }));
  }  // closed before any tick adopted it
  ASSERT_TRUE(wait_until([&] { return !f.hub->link(0)->claimed(); }));
  ExternalClient next = f.client(true);
  EXPECT_NO_THROW(next.connect());
}

}  // namespace
}  // namespace rfsitl::external
