/// The handshake's JSON from the other side is read with every number checked
/// as a double before it becomes an integer (node_id 4294967298 must not alias
/// node 2, 1e30 must not reach a float-to-integer cast), and its strings reach
/// the emulator's log escaped.
#include "rfsitl/external/client/handshake.hpp"

#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "external_test_support.hpp"
#include "log_capture.hpp"
#include "rfsitl/external/client/external_client.hpp"
#include "rfsitl/external/client/message_channel.hpp"
#include "rfsitl/external/external_hub.hpp"

namespace rfsitl::external {
namespace {

using ::rfsitl::testing::LogCapture;
using testing::JoiningThread;
using testing::SocketPath;

/// The HandshakeError message of reading `text` with `read` ("" if it reads).
template <class Read>
std::string error_of(Read read, const std::string& text) {
  try {
    read(text);
  } catch (const HandshakeError& e) {
    return e.what();
  }
  return "";
}

std::string hello_error(const std::string& text) {
  return error_of(read_hello, text);
}
std::string welcome_error(const std::string& text) {
  return error_of(read_welcome, text);
}

TEST(ExternalHandshake, HelloNodeIdIsRangeCheckedBeforeItBecomesAnInteger) {
  const auto with_id = [](const std::string& id) {
    return R"({"node_id": )" + id + R"(, "role": "samples"})";
  };
  // 2^32 + 2 would be node 2 after a cast to 32 bits; 1e30 has no integer type at all.
  EXPECT_EQ(hello_error(with_id("4294967298")), "node_id 4294967298 out of range 1..254");
  EXPECT_EQ(hello_error(with_id("1e30")), "node_id 1e+30 out of range 1..254");
  EXPECT_EQ(hello_error(with_id("-1e30")), "node_id -1e+30 out of range 1..254");
  EXPECT_EQ(hello_error(with_id("-1")), "node_id -1 out of range 1..254");
  EXPECT_EQ(hello_error(with_id("0")), "node_id 0 out of range 1..254");
  EXPECT_EQ(hello_error(with_id("255")), "node_id 255 out of range 1..254");
  EXPECT_EQ(hello_error(with_id("258")), "node_id 258 out of range 1..254");  // 2 as a u8
  EXPECT_EQ(hello_error(with_id("2.5")), "node_id: expected an integer, got 2.5");
  EXPECT_EQ(hello_error(with_id("\"2\"")), "node_id: expected an integer, got \"2\"");
  EXPECT_EQ(hello_error(with_id("1e400")), "not JSON (a number beyond any double)");
  EXPECT_EQ(read_hello(with_id("254")).node_id, 254);
  EXPECT_EQ(read_hello(with_id("2.0")).node_id, 2);  // an integral number is an integer
}

TEST(ExternalHandshake, HelloNeedsItsFieldsWithTheirTypes) {
  EXPECT_EQ(hello_error(R"({"role": "samples"})"), "node_id: missing");
  EXPECT_EQ(hello_error(R"({"node_id": 2})"), "role: missing");
  EXPECT_EQ(hello_error(R"({"node_id": 2, "role": 7})"), "role: expected a string, got 7");
  EXPECT_EQ(hello_error(R"({"node_id": 2, "role": "samples", "program": [1]})"),
            "program: expected a string, got [1]");
  EXPECT_EQ(hello_error("[2]"), "expected a JSON object, got [2]");
  EXPECT_EQ(hello_error("{\"node_id\": "), "not JSON (syntax error at byte 13)");
  const Hello h = read_hello(R"({"node_id": 7, "role": "transceiver", "program": "gr"})");
  EXPECT_EQ(h.node_id, 7);
  EXPECT_EQ(h.role, "transceiver");
  EXPECT_EQ(h.program, "gr");
  EXPECT_EQ(read_hello(hello_json(h)).program, "gr");
  EXPECT_EQ(read_hello(R"({"node_id": 7, "role": "samples"})").program, "external");
}

TEST(ExternalHandshake, WelcomeNumbersAreRangeCheckedBeforeTheyBecomeIntegers) {
  const Welcome good{5, 2.5e6, 320, true, R"({"type":"gmsk"})"};
  const Welcome back = read_welcome(welcome_json(good));
  EXPECT_EQ(back.node_id, 5);
  EXPECT_EQ(back.sample_rate_hz, 2.5e6);
  EXPECT_EQ(back.tick_samples, 320U);
  EXPECT_TRUE(back.virtual_time);
  EXPECT_EQ(back.phy_json, good.phy_json);

  const auto with = [](const std::string& field, const std::string& value) {
    std::string j = R"({"protocol": 1, "node_id": 5, "sample_rate_hz": 1e6, "tick_samples": 250,)"
                    R"( "time_mode": "virtual"})";
    const auto at = j.find("\"" + field + "\"");
    const auto from = j.find(':', at) + 2;
    const auto to = j.find_first_of(",}", from);
    return j.replace(from, to - from, value);
  };
  EXPECT_EQ(welcome_error(with("protocol", "1e30")), "protocol 1e+30, this program speaks 1");
  EXPECT_EQ(welcome_error(with("protocol", "2")), "protocol 2, this program speaks 1");
  EXPECT_EQ(welcome_error(with("node_id", "4294967301")), "node_id 4294967301 out of range 1..254");
  EXPECT_EQ(welcome_error(with("tick_samples", "1e30")),
            "tick_samples 1e+30 out of range 1..16384");
  EXPECT_EQ(welcome_error(with("tick_samples", "4294967296")),
            "tick_samples 4294967296 out of range 1..16384");
  EXPECT_EQ(welcome_error(with("tick_samples", "0")), "tick_samples 0 out of range 1..16384");
  EXPECT_EQ(welcome_error(with("sample_rate_hz", "-1")),
            "sample_rate_hz: expected a finite number > 0, got -1");
  EXPECT_EQ(welcome_error(with("sample_rate_hz", "null")),
            "sample_rate_hz: expected a finite number > 0, got null");
  EXPECT_EQ(welcome_error(with("time_mode", "\"fast\"")),
            "time_mode: expected \"realtime\" or \"virtual\", got \"fast\"");
}

/// A stand-in emulator: answers one connection's hello with `welcome`.
class OneWelcome {
 public:
  OneWelcome(const std::string& path, std::string welcome) {
    fd_ = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
    if (::bind(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0 ||
        ::listen(fd_, 1) != 0) {
      throw std::runtime_error("stand-in emulator cannot listen on " + path);
    }
    thread_ = JoiningThread([this, w = std::move(welcome)] {
      MessageChannel ch(::accept4(fd_, nullptr, nullptr, SOCK_CLOEXEC));
      Message hello;
      if (ch.receive(hello, 5000) != RecvStatus::kOk) return;
      MsgHeader h;
      h.type = static_cast<std::uint16_t>(MsgType::kWelcome);
      ch.send(h, {}, {reinterpret_cast<const std::uint8_t*>(w.data()), w.size()});
      ch.receive(hello, 5000);  // until the client hangs up
    });
  }
  ~OneWelcome() {
    thread_.join();
    ::close(fd_);
  }
  OneWelcome(const OneWelcome&) = delete;
  OneWelcome& operator=(const OneWelcome&) = delete;

 private:
  int fd_ = -1;
  JoiningThread thread_;
};

TEST(ExternalHandshake, ClientRefusesAWelcomeForAnotherNodeModulo256) {
  // 4294967301 = 2^32 + 5: read as a u8 it would be the node the client asked for.
  SocketPath path;
  {
    OneWelcome emulator(path.str(),
                        R"({"protocol": 1, "node_id": 4294967301, "sample_rate_hz": 1e6,)"
                        R"( "tick_samples": 250, "time_mode": "virtual"})");
    ExternalClient client({path.str(), 5, "samples", "unit-test", 5000});
    try {
      client.connect();
      ADD_FAILURE() << "a welcome for node 4294967301 was taken as one for node 5";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("bad welcome: node_id 4294967301 out of range 1..254"),
                std::string::npos)
          << e.what();
    }
    EXPECT_FALSE(client.connected());
  }
  ::unlink(path.str().c_str());
  {
    OneWelcome emulator(path.str(), R"({"protocol": 1, "node_id": 6, "sample_rate_hz": 1e6,)"
                                    R"( "tick_samples": 250, "time_mode": "virtual"})");
    ExternalClient client({path.str(), 5, "samples", "unit-test", 5000});
    try {
      client.connect();
      ADD_FAILURE() << "a welcome for node 6 was taken as one for node 5";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("bad welcome: it is for node 6"), std::string::npos)
          << e.what();
    }
  }
}

/// The hub's answer to a hello with `text` as its JSON.
Message hub_answer(const std::string& path, const std::string& text) {
  MessageChannel ch = MessageChannel::connect_to(path);
  MsgHeader h;
  h.type = static_cast<std::uint16_t>(MsgType::kHello);
  EXPECT_TRUE(ch.send(h, {}, {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()}));
  Message m;
  EXPECT_EQ(ch.receive(m, 5000), RecvStatus::kOk);
  return m;
}

TEST(ExternalHandshake, HubRefusesANodeIdThatWouldAliasADeclaredNode) {
  SocketPath path;
  HubSettings hs;
  hs.socket_path = path.str();
  const auto hub = make_external_hub(hs, {ExternalNodeSpec{0, 2, Role::kSamples, ""}});
  for (const std::string id : {"4294967298", "258", "1e30", "2.5"}) {
    const Message m = hub_answer(path.str(), R"({"node_id": )" + id + R"(, "role": "samples"})");
    EXPECT_EQ(m.type(), MsgType::kReject) << id << " admitted as node 2";
    EXPECT_EQ(m.extra_text().rfind("bad hello JSON: node_id", 0), 0U) << m.extra_text();
  }
  EXPECT_EQ(hub_answer(path.str(), R"({"node_id": 1e30, "role": "samples"})").extra_text(),
            "bad hello JSON: node_id 1e+30 out of range 1..254");
  EXPECT_EQ(hub->rejected(), 5U);
  EXPECT_EQ(hub->never_joined(), std::vector<NodeId>{2});
  // Node 2 itself is still welcome.
  EXPECT_EQ(hub_answer(path.str(), R"({"node_id": 2, "role": "samples"})").type(),
            MsgType::kWelcome);
}

TEST(ExternalHandshake, ClientStringsReachTheLogEscaped) {
  SocketPath path;
  HubSettings hs;
  hs.socket_path = path.str();
  const auto hub = make_external_hub(hs, {ExternalNodeSpec{0, 2, Role::kSamples, ""}});
  const std::string forged = "\n[2030-01-01 00:00:00.000] [error] forged\x1b[2J";
  LogCapture log;
  // Refused: the role (the client's words) is quoted in the refusal.
  EXPECT_EQ(hub_answer(path.str(), R"({"node_id": 2, "role": "x\n[error] forged"})").type(),
            MsgType::kReject);
  // Admitted: the program name is printed when the node joins and is dropped.
  ExternalClient client({path.str(), 2, "samples", "gr" + forged, 5000});
  client.connect();
  const auto link = hub->link(0);
  ASSERT_TRUE(testing::wait_until([&] { return link->adopt(); }));
  link->drop("test");
  const auto refused = log.lines_with("refused a connection");
  ASSERT_EQ(refused.size(), 1U);
  EXPECT_NE(refused[0].find("connected as 'x\\n[error] forged'"), std::string::npos) << refused[0];
  const auto joined = log.lines_with("joined");
  const auto dropped = log.lines_with("dropped");
  ASSERT_EQ(joined.size(), 1U);
  ASSERT_EQ(dropped.size(), 1U);
  EXPECT_NE(joined[0].find("'gr\\n[2030-01-01 00:00:00.000] [error] forged\\x1b[2J'"),
            std::string::npos)
      << joined[0];
  for (const auto& line : log.lines()) {
    EXPECT_EQ(line.find_first_of("\n\r\x1b"), std::string::npos) << line;
  }
}

}  // namespace
}  // namespace rfsitl::external
