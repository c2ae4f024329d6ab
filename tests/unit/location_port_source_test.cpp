// The location port as a position source, without an engine: real loopback
// sockets on one side, a spy sink on the other.
#include "rfsitl/position/location_port/location_port_source.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "rfsitl/io/port_error.hpp"
#include "rfsitl/registry/position_source_registry.hpp"
#include "spy_position_sink.hpp"

namespace rfsitl::position {
namespace {

using namespace std::chrono_literals;

/// A loopback port that was free a moment ago.
std::uint16_t free_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  EXPECT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  socklen_t len = sizeof a;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  ::close(fd);
  return ntohs(a.sin_port);
}

/// A blocking client connection to a loopback port.
class Client {
 public:
  explicit Client(std::uint16_t port) : fd_(::socket(AF_INET, SOCK_STREAM, 0)) {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    EXPECT_EQ(::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a), 0) << "port " << port;
  }
  ~Client() { close(); }
  void send(const std::string& text) {
    ASSERT_EQ(::send(fd_, text.data(), text.size(), MSG_NOSIGNAL),
              static_cast<ssize_t>(text.size()));
  }
  void close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

 private:
  int fd_;
};

SourceNode node(std::size_t index, NodeId id, std::uint16_t port, double stale_after_s = 0.0) {
  SourceNode n{index, id,
               location_port_settings().info("position", "location_port", "").defaults()};
  n.settings.set("port", std::uint64_t{port});
  n.settings.set("stale_after_s", stale_after_s);
  return n;
}

/// A started source of one node (index `index`, id `id`) on a free port: a port
/// found free may be taken by another test before the source binds it, so a
/// port in use is retried with another.
struct Started {
  std::unique_ptr<PositionSource> source;
  std::uint16_t port = 0;
};
Started start_one(PositionSink& sink, std::size_t index, NodeId id, double stale_after_s = 0.0) {
  for (int attempt = 0;; ++attempt) {
    const std::uint16_t port = free_port();
    auto source = make_location_port_source({}, {node(index, id, port, stale_after_s)});
    try {
      source->start(sink);
      return {std::move(source), port};
    } catch (const io::PortError&) {
      if (attempt == 20) throw;
    }
  }
}

/// Polls `counters(index)` until `done` holds or 20 s pass.
template <typename Pred>
SourceCounters wait_counters(const PositionSource& s, std::size_t index, Pred done) {
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  SourceCounters c = *s.counters(index);
  while (!done(c) && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(5ms);
    c = *s.counters(index);
  }
  return c;
}

TEST(LocationPortSource, IsRegisteredAndUsableInVirtualTime) {
  const auto* c = find_position_source("location_port");
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(c->info.kind, "position");
  EXPECT_FALSE(c->wall_clock);
}

TEST(LocationPortSource, ReportsEveryFormatAndCountsBadLines) {
  test::SpyPositionSink sink;
  auto [source, port] = start_one(sink, 3, 4);
  EXPECT_EQ(source->where(3), "127.0.0.1:" + std::to_string(port));
  EXPECT_EQ(source->counters(0), std::nullopt);
  EXPECT_EQ(source->where(0), "");
  {
    Client feed(port);
    feed.send("43.5 -78.25 120\n\n{\"x\": 1, \"y\": -2, \"z\": 30}\nnot a position\n");
    const auto got = sink.wait_for(2);
    ASSERT_EQ(got.size(), 2U);
    EXPECT_EQ(got[0].first, 3U);
    const auto* geo = std::get_if<GeodeticPosition>(&*got[0].second.position);
    ASSERT_NE(geo, nullptr);
    EXPECT_DOUBLE_EQ(geo->lat_deg, 43.5);
    EXPECT_DOUBLE_EQ(geo->lon_deg, -78.25);
    EXPECT_DOUBLE_EQ(geo->alt_m, 120.0);
    EXPECT_FALSE(got[0].second.velocity.has_value());
    const auto* local = std::get_if<LocalPosition>(&*got[1].second.position);
    ASSERT_NE(local, nullptr);
    EXPECT_DOUBLE_EQ(local->y_m, -2.0);
    const SourceCounters c = wait_counters(*source, 3, [](const auto& k) { return k.errors == 1; });
    EXPECT_EQ(c.updates, 2U);
    EXPECT_EQ(c.errors, 1U);  // the blank line is neither
    EXPECT_TRUE(c.connected);
    EXPECT_EQ(c.reconnects, 0U);
    ASSERT_TRUE(c.last_update_age_s.has_value());
    EXPECT_GE(*c.last_update_age_s, 0.0);
    EXPECT_FALSE(c.stale);  // stale_after_s 0: never
  }
  const SourceCounters closed =
      wait_counters(*source, 3, [](const auto& k) { return !k.connected; });
  EXPECT_FALSE(closed.connected);
  source->stop();
  EXPECT_EQ(sink.count(), 2U);
}

TEST(LocationPortSource, ALastLineWithoutNewlineIsUsedAndAnOverlongLineIsRefused) {
  test::SpyPositionSink sink;
  auto [source, port] = start_one(sink, 0, 1);
  {
    Client feed(port);
    feed.send(std::string(kMaxLocationLine + 10, '1') + "\n");
    feed.send("{\"x\": 5, \"y\": 0}");  // then EOF
  }
  ASSERT_EQ(sink.wait_for(1).size(), 1U);
  // A position reaches the sink before it is counted (so that a frame sent
  // after the count goes on the air with it): wait for the count too.
  const SourceCounters c =
      wait_counters(*source, 0, [](const auto& k) { return k.errors == 1 && k.updates == 1; });
  EXPECT_EQ(c.errors, 1U);
  EXPECT_EQ(c.updates, 1U);
  const auto overlong = std::find_if(c.detail.begin(), c.detail.end(),
                                     [](const auto& d) { return d.first == "overlong_lines"; });
  ASSERT_NE(overlong, c.detail.end());
  EXPECT_EQ(overlong->second, 1U);
}

TEST(LocationPortSource, CountsReconnectsAndTurnsStaleWhenSilent) {
  test::SpyPositionSink sink;
  auto [source, port] = start_one(sink, 0, 1, 0.05);
  {
    Client first(port);
    first.send("1 2 3\n");
    sink.wait_for(1);
  }
  wait_counters(*source, 0, [](const auto& k) { return !k.connected; });
  Client second(port);
  second.send("1 2 4\n");
  ASSERT_EQ(sink.wait_for(2).size(), 2U);
  const SourceCounters c = wait_counters(*source, 0, [](const auto& k) { return k.stale; });
  EXPECT_EQ(c.reconnects, 1U);
  EXPECT_TRUE(c.stale);
  EXPECT_GT(*c.last_update_age_s, 0.05);
}

TEST(LocationPortSource, PortsDeriveFromTheRunsBaseUnlessANodeNamesOne) {
  LocationPortSettings s;
  EXPECT_EQ(location_port_number(s, 15766, 3), 15796);
  s.port = 16000;
  EXPECT_EQ(location_port_number(s, 15766, 3), 16000);
  EXPECT_THROW(location_port_number(LocationPortSettings{}, 65000, 60), std::invalid_argument);
}

TEST(LocationPortSource, TwoNodesOnOnePortAreRefusedNamingBoth) {
  try {
    make_location_port_source({}, {node(0, 1, 16000), node(1, 2, 16000)});
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("nodes 1 and 2"), std::string::npos) << e.what();
  }
}

TEST(LocationPortSource, APortInUseFailsTheStartNamingNodeAndPort) {
  const std::uint16_t port = free_port();
  const int squatter = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::bind(squatter, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  ASSERT_EQ(::listen(squatter, 1), 0);
  auto source = make_location_port_source({}, {node(0, 7, port)});
  test::SpyPositionSink sink;
  try {
    source->start(sink);
    FAIL() << "no error";
  } catch (const io::PortError& e) {
    EXPECT_NE(std::string(e.what()).find("location port " + std::to_string(port) + " of node 7"),
              std::string::npos)
        << e.what();
  }
  source->stop();  // after a failed start: nothing to join, no crash
  ::close(squatter);
}

}  // namespace
}  // namespace rfsitl::position
