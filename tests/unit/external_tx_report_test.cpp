/// The samples role's kTx report (tx_report.hpp): its bytes, the welcome field
/// that asks for it, and the emulator's proxy adding what a program reports
/// (RX overflows) to the node's counter, from each connection's welcome on.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <cstring>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "external_samples_hub.hpp"
#include "external_test_support.hpp"
#include "rfsitl/external/client/external_client.hpp"
#include "rfsitl/external/client/handshake.hpp"
#include "rfsitl/external/client/tx_report.hpp"
#include "rfsitl/external/external_hub.hpp"
#include "rfsitl/external/external_transceivers.hpp"

namespace rfsitl::external {
namespace {

using testing::SocketPath;
using testing::wait_until;

constexpr std::uint32_t kB = 32;
constexpr NodeId kNode = 6;

TEST(ExternalTxReport, BytesRoundTripAndAnEmptyExtraIsNoReport) {
  TxReport r;
  r.rx_overflows = 0x0102030405060708ULL;
  const auto bytes = tx_report_bytes(r);
  const auto back = read_tx_report(bytes);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->version, kTxReportVersion);
  EXPECT_EQ(back->rx_overflows, r.rx_overflows);
  EXPECT_FALSE(read_tx_report({}).has_value()) << "a program older than reports";
}

TEST(ExternalTxReport, ALaterVersionIsReadByItsVersion1Prefix) {
  TxReport r;
  r.version = 2;
  r.rx_overflows = 9;
  std::vector<std::uint8_t> bytes(sizeof r + 8, 0xAB);  // a field version 1 does not know
  std::memcpy(bytes.data(), &r, sizeof r);
  const auto back = read_tx_report(bytes);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->rx_overflows, 9U);
}

TEST(ExternalTxReport, ShortOrVersionZeroExtrasAreRefusedNamingWhy) {
  const std::vector<std::uint8_t> shorter(sizeof(TxReport) - 1, 1);
  try {
    read_tx_report(shorter);
    FAIL() << "a 15-byte report was read";
  } catch (const TxReportError& e) {
    EXPECT_NE(std::string(e.what()).find("15 bytes"), std::string::npos) << e.what();
  }
  TxReport zero;
  zero.version = 0;
  EXPECT_THROW(read_tx_report(tx_report_bytes(zero)), TxReportError);
}

TEST(ExternalTxReport, WelcomeNamesTheVersionItReadsAndAnOlderWelcomeNone) {
  Welcome w{kNode, 1e6, kB, false, "", kTxReportVersion};
  EXPECT_EQ(read_welcome(welcome_json(w)).tx_report, kTxReportVersion);
  w.tx_report = 0;
  const std::string older = welcome_json(w);
  EXPECT_EQ(older.find("tx_report"), std::string::npos) << older;
  EXPECT_EQ(read_welcome(older).tx_report, 0U);
  for (const char* bad : {"-1", "2.5", "\"1\"", "1e9"}) {
    const std::string text = R"({"protocol":1,"node_id":6,"sample_rate_hz":1e6,)"
                             R"("tick_samples":32,"time_mode":"realtime","tx_report":)" +
                             std::string(bad) + "}";
    EXPECT_THROW(read_welcome(text), HandshakeError) << bad;
  }
}

/// The hub and proxy of one samples node, and the program's ticks.
struct Fixture : testing::SamplesHub {
  Fixture() : SamplesHub(kNode, kB) {}
  std::uint64_t next_tick = 1;

  std::unique_ptr<ExternalClient> join() {
    auto c = std::make_unique<ExternalClient>(
        ExternalClient::Settings{path.str(), kNode, "samples", "unit-test", 3000, false});
    EXPECT_EQ(c->connect().tx_report, kTxReportVersion) << "the hub asks for reports";
    return c;
  }

  /// One tick: the program answers with `extra` after its samples (raw, so
  /// that a malformed one can be sent too). False if the link dropped.
  bool tick(ExternalClient& c, std::span<const std::uint8_t> extra) {
    const std::uint64_t k = next_tick++;
    port->begin_tick(k, static_cast<SampleTime>(k * kB));
    std::vector<cf32> out(kB);
    testing::JoiningThread program([&] {
      if (c.wait_tick(3000) != RecvStatus::kOk) return;
      MsgHeader h;
      h.type = static_cast<std::uint16_t>(MsgType::kTx);
      h.tick = c.tick().index;
      h.time = c.tick().time;
      c.channel().send(h, {}, extra);
    });
    port->transmit(out);
    return link->connected();
  }
};

TEST(ExternalTxReport, ProxyAddsTheGrowthOfEachConnectionsTotal) {
  Fixture f;
  auto c = f.join();
  ASSERT_TRUE(wait_until([&] { return f.hub->never_joined().empty(); }));
  TxReport r;
  for (const std::uint64_t total : {0, 2, 2, 5}) {
    r.rx_overflows = total;
    ASSERT_TRUE(f.tick(*c, tx_report_bytes(r)));
  }
  EXPECT_EQ(f.overflows.load(), 5U);
  ASSERT_TRUE(f.tick(*c, {})) << "a kTx without a report is still a kTx";
  EXPECT_EQ(f.overflows.load(), 5U);
  r.rx_overflows = 3;  // a total that shrinks adds nothing
  ASSERT_TRUE(f.tick(*c, tx_report_bytes(r)));
  EXPECT_EQ(f.overflows.load(), 5U);

  // A new connection counts from its own welcome: its total 1 is new. (The
  // hub offers it after sending the welcome: adopted once it is there.)
  c = f.join();
  ASSERT_TRUE(wait_until([&] {
    f.port->begin_tick(f.next_tick, static_cast<SampleTime>(f.next_tick * kB));
    return f.link->joins() == 2;
  }));
  r.rx_overflows = 1;
  ASSERT_TRUE(f.tick(*c, tx_report_bytes(r)));
  EXPECT_EQ(f.link->joins(), 2U);
  EXPECT_EQ(f.overflows.load(), 6U);
}

TEST(ExternalTxReport, AnExtraThatIsNoReportDropsTheProgram) {
  Fixture f;
  auto c = f.join();
  ASSERT_TRUE(wait_until([&] { return f.hub->never_joined().empty(); }));
  const std::vector<std::uint8_t> junk(3, 0xFF);
  EXPECT_FALSE(f.tick(*c, junk));
  EXPECT_EQ(f.link->drops(), 1U);
  EXPECT_EQ(f.overflows.load(), 0U);
}

TEST(ExternalTxReport, ClientsSendTxWithAReportReachesTheCounter) {
  Fixture f;
  auto c = f.join();
  ASSERT_TRUE(wait_until([&] { return f.hub->never_joined().empty(); }));
  f.port->begin_tick(1, kB);
  std::vector<cf32> out(kB);
  testing::JoiningThread program([&] {
    if (c->wait_tick(3000) != RecvStatus::kOk) return;
    TxReport r;
    r.rx_overflows = 4;
    c->send_tx({}, r);
  });
  f.port->transmit(out);
  program.join();
  EXPECT_EQ(f.overflows.load(), 4U);
}

}  // namespace
}  // namespace rfsitl::external
