// With a control token (the dashboard reachable beyond loopback, or a token the
// user gave), moving nodes needs it: a move without it or with a wrong one is
// refused and counted, with the right one applied; watching never needs it.
#include "rfsitl/monitor/control_token.hpp"

#include <gtest/gtest.h>

#include <set>

#include <nlohmann/json.hpp>

#include "dashboard_test_support.hpp"
#include "rfsitl/common/geodesy.hpp"

namespace rfsitl::monitor {
namespace {

namespace http = test::http;
using test::LiveDashboard;
using test::request;
using Json = nlohmann::json;

constexpr std::string_view kToken = "s3cret-Token_0123.~";

TEST(DashboardControlToken, OnlyLoopbackBindAddressesNeedNoToken) {
  for (const std::string_view a : {"127.0.0.1", "127.0.0.2", "127.255.0.9", "::1", "localhost",
                                   "LocalHost", "::ffff:127.0.0.1"}) {
    EXPECT_TRUE(bind_is_loopback(a)) << a;
  }
  for (const std::string_view a : {"0.0.0.0", "::", "10.213.0.1", "192.168.1.5", "fe80::1",
                                   "::ffff:10.0.0.1", "example.com", ""}) {
    EXPECT_FALSE(bind_is_loopback(a)) << a;
  }
}

TEST(DashboardControlToken, UserTokensMustBeLongAndUrlSafe) {
  EXPECT_EQ(control_token_problem(kToken), "");
  EXPECT_EQ(control_token_problem(std::string(256, 'a')), "");
  EXPECT_NE(control_token_problem(""), "");
  EXPECT_NE(control_token_problem(std::string(15, 'a')), "") << "16 is the minimum";
  EXPECT_EQ(control_token_problem(std::string(16, 'a')), "");
  EXPECT_NE(control_token_problem(std::string(257, 'a')), "");
  EXPECT_NE(control_token_problem("with space in it ok?"), "");
  EXPECT_NE(control_token_problem("percent%20escaped-x"), "");
  EXPECT_NE(control_token_problem("ampersand&token=xyz"), "");
}

TEST(DashboardControlToken, DrawnTokensAre128RandomBitsInHex) {
  std::set<std::string> seen;
  for (int i = 0; i < 64; ++i) {
    const std::string t = generate_control_token();
    ASSERT_EQ(t.size(), 32U) << t;
    EXPECT_EQ(t.find_first_not_of("0123456789abcdef"), std::string::npos) << t;
    EXPECT_EQ(control_token_problem(t), "") << t;
    seen.insert(t);
  }
  EXPECT_EQ(seen.size(), 64U) << "a drawn token repeated";
}

TEST(DashboardControlToken, MatchesOnlyTheExactToken) {
  const std::string t(kToken);
  EXPECT_TRUE(control_token_matches(t, t));
  std::string last = t;
  last.back() = 'x';
  std::string first = t;
  first.front() = 'x';
  EXPECT_FALSE(control_token_matches(last, t));
  EXPECT_FALSE(control_token_matches(first, t));
  EXPECT_FALSE(control_token_matches(t.substr(0, t.size() - 1), t)) << "a prefix";
  EXPECT_FALSE(control_token_matches(t + "x", t)) << "longer";
  EXPECT_FALSE(control_token_matches("", t));
  EXPECT_FALSE(control_token_matches(std::string(t.size(), '\0'), t));
}

TEST(DashboardControlToken, ReadFromTheBearerHeaderOrTheTokenQueryParameter) {
  EXPECT_EQ(request_control_token("/ws?token=abc", std::nullopt), "abc");
  EXPECT_EQ(request_control_token("/ws?x=1&token=abc&y=2", std::nullopt), "abc");
  EXPECT_EQ(request_control_token("/ws?mytoken=no&token=a%2Db%7E", std::nullopt), "a-b~");
  EXPECT_EQ(request_control_token("/ws?token=", std::nullopt), "");
  EXPECT_EQ(request_control_token("/ws?token=bad%2", std::nullopt), std::nullopt);
  EXPECT_EQ(request_control_token("/ws", std::nullopt), std::nullopt);
  EXPECT_EQ(request_control_token("/ws?tokens=abc", std::nullopt), std::nullopt);
  EXPECT_EQ(request_control_token("/ws", "Bearer abc"), "abc");
  EXPECT_EQ(request_control_token("/ws", "bearer   abc  "), "abc");
  EXPECT_EQ(request_control_token("/ws?token=query", "Bearer header"), "header");
  // Another scheme is no token; the query still counts.
  EXPECT_EQ(request_control_token("/ws", "Basic YWJjOmRlZg=="), std::nullopt);
  EXPECT_EQ(request_control_token("/ws?token=q", "Basic YWJjOmRlZg=="), "q");
  EXPECT_EQ(request_control_token("/ws", "Bearerabc"), std::nullopt);
}

TEST(DashboardControlToken, RefusalSaysWhetherTheTokenIsMissingOrWrong) {
  EXPECT_EQ(control_token_refusal("/ws", std::nullopt, ""), "") << "no token required";
  EXPECT_EQ(control_token_refusal("/ws?token=whatever", std::nullopt, ""), "");
  const std::string t(kToken);
  EXPECT_EQ(control_token_refusal("/ws?token=" + t, std::nullopt, t), "");
  EXPECT_EQ(control_token_refusal("/api/nodes/1/position", "Bearer " + t, t), "");
  const std::string missing = control_token_refusal("/ws", std::nullopt, t);
  EXPECT_NE(missing.find("needs the dashboard's control token"), std::string::npos) << missing;
  const std::string empty = control_token_refusal("/ws?token=", std::nullopt, t);
  EXPECT_NE(empty.find("needs"), std::string::npos) << empty;
  const std::string wrong = control_token_refusal("/ws?token=" + t + "x", std::nullopt, t);
  EXPECT_NE(wrong.find("wrong control token"), std::string::npos) << wrong;
  EXPECT_EQ(wrong.find(t), std::string::npos) << "the refusal must not echo a token";
}

/// A dashboard with control on that requires kToken.
DashboardSettings token_settings() {
  DashboardSettings settings;
  settings.control = true;
  settings.control_token = std::string(kToken);
  return settings;
}

/// Node 1's local position after running the engine (virtual time, a few ticks).
LocalPosition node1_after_run(LiveDashboard& d) {
  const std::atomic<bool> stop{false};
  d.engine->run(stop);
  const auto where = d.engine->positions().at(0);
  EXPECT_TRUE(where.has_value());
  return ecef_to_local(*where, d.s.channel.origin);
}

TEST(DashboardControlToken, PostMovesOnlyWithTheRightBearerToken) {
  LiveDashboard d(token_settings());
  const std::string body = R"({"x": 5, "y": 6, "z": 7})";
  const auto missing = request(d.port(), http::verb::post, "/api/nodes/1/position", body);
  EXPECT_EQ(missing.result(), http::status::unauthorized) << missing.body();
  EXPECT_NE(missing[http::field::www_authenticate].find("Bearer"), std::string::npos);
  EXPECT_NE(missing.body().find("control token"), std::string::npos) << missing.body();
  // Refused before the node id is looked at: nothing about the run leaks.
  const auto unknown = request(d.port(), http::verb::post, "/api/nodes/99/position", body);
  EXPECT_EQ(unknown.result(), http::status::unauthorized) << unknown.body();
  const auto wrong = request(d.port(), http::verb::post, "/api/nodes/1/position", body,
                             {{http::field::authorization, "Bearer " + std::string(kToken) + "x"}});
  EXPECT_EQ(wrong.result(), http::status::unauthorized) << wrong.body();
  EXPECT_NE(wrong.body().find("wrong control token"), std::string::npos) << wrong.body();
  EXPECT_EQ(d.dashboard->control_refused(), 3U);
  // Viewing needs no token.
  EXPECT_EQ(request(d.port(), http::verb::get, "/api/stats").result(), http::status::ok);
  const auto metrics = request(d.port(), http::verb::get, "/metrics");
  EXPECT_NE(metrics.body().find("rfsitl_dashboard_control_refused_total 3\n"), std::string::npos)
      << metrics.body();
  // Nothing moved yet: node 1 would still be at its scenario position...
  const auto right = request(d.port(), http::verb::post, "/api/nodes/1/position", body,
                             {{http::field::authorization, "Bearer " + std::string(kToken)}});
  EXPECT_EQ(right.result(), http::status::ok) << right.body();
  // ...and the query parameter works too (a later move wins).
  const auto by_query =
      request(d.port(), http::verb::post, "/api/nodes/1/position?token=" + std::string(kToken),
              R"({"x": 8, "y": 6, "z": 7})");
  EXPECT_EQ(by_query.result(), http::status::ok) << by_query.body();
  EXPECT_EQ(d.dashboard->control_refused(), 3U);
  const LocalPosition l = node1_after_run(d);
  EXPECT_NEAR(l.x_m, 8.0, 1e-6);
  EXPECT_NEAR(l.y_m, 6.0, 1e-6);
}

TEST(DashboardControlToken, RefusedPostsLeaveTheNodeWhereItWas) {
  LiveDashboard d(token_settings());
  const auto res =
      request(d.port(), http::verb::post, "/api/nodes/1/position", R"({"x": 5, "y": 6, "z": 7})",
              {{http::field::authorization, "Bearer not-the-token-at-all"}});
  EXPECT_EQ(res.result(), http::status::unauthorized);
  const LocalPosition l = node1_after_run(d);
  EXPECT_NEAR(l.x_m, 0.0, 1e-6);  // two_nodes(): node 1 at (0, 0, 10)
  EXPECT_NEAR(l.z_m, 10.0, 1e-6);
}

/// A viewer whose upgrade asks for `target`; its hello.
Json open_viewer(test::Viewer& v, std::uint16_t port, const std::string& target) {
  test::beast::error_code ec;
  v.ws.next_layer().connect(test::tcp::endpoint(test::asio::ip::make_address("127.0.0.1"), port),
                            ec);
  EXPECT_FALSE(ec) << ec.message();
  v.ws.handshake(v.res, "127.0.0.1:" + std::to_string(port), target, ec);
  EXPECT_FALSE(ec) << target << ": " << ec.message();
  const Json hello = Json::parse(v.read());
  EXPECT_EQ(hello.at("type"), "hello");
  return hello;
}

TEST(DashboardControlToken, ViewerWithoutTheTokenWatchesButCannotMove) {
  LiveDashboard d(token_settings());
  test::Viewer without;
  const Json hello = open_viewer(without, d.port(), "/ws");
  EXPECT_EQ(hello.at("control"), false);
  EXPECT_NE(hello.value("control_refused", "").find("control token"), std::string::npos)
      << hello.dump();
  without.write(R"({"type": "watch", "node": 2})");
  without.write(R"({"type": "move", "node": 1, "x": 5, "y": 6, "z": 7})");
  const auto errors = test::errors_until_end(without);
  ASSERT_EQ(errors.size(), 1U) << "watch is allowed, the move is not";
  EXPECT_NE(errors[0].find("needs the dashboard's control token"), std::string::npos) << errors[0];

  test::Viewer wrong;
  const Json wrong_hello = open_viewer(wrong, d.port(), "/ws?token=" + std::string(kToken) + "0");
  EXPECT_EQ(wrong_hello.at("control"), false);
  wrong.write(R"({"type": "move", "node": 1, "x": 5, "y": 6, "z": 7})");
  const auto wrong_errors = test::errors_until_end(wrong);
  ASSERT_EQ(wrong_errors.size(), 1U);
  EXPECT_NE(wrong_errors[0].find("wrong control token"), std::string::npos) << wrong_errors[0];
  EXPECT_EQ(d.dashboard->control_refused(), 2U);
  EXPECT_EQ(d.dashboard->viewers(), 2U) << "refused viewers still watch";

  const LocalPosition l = node1_after_run(d);
  EXPECT_NEAR(l.x_m, 0.0, 1e-6);
}

TEST(DashboardControlToken, ViewerWithTheTokenMoves) {
  LiveDashboard d(token_settings());
  test::Viewer v;
  const Json hello = open_viewer(v, d.port(), "/ws?token=" + std::string(kToken));
  EXPECT_EQ(hello.at("control"), true);
  EXPECT_FALSE(hello.contains("control_refused"));
  v.write(R"({"type": "move", "node": 1, "x": 5, "y": 6, "z": 7})");
  EXPECT_TRUE(test::errors_until_end(v).empty());
  EXPECT_EQ(d.dashboard->control_refused(), 0U);
  const LocalPosition l = node1_after_run(d);
  EXPECT_NEAR(l.x_m, 5.0, 1e-6);
  EXPECT_NEAR(l.y_m, 6.0, 1e-6);
}

TEST(DashboardControlToken, WithoutATokenControlNeedsNone) {
  DashboardSettings settings;
  settings.control = true;  // loopback, no token given: as before
  LiveDashboard d(settings);
  test::Viewer v;
  const Json hello = open_viewer(v, d.port(), "/ws");
  EXPECT_EQ(hello.at("control"), true);
  v.write(R"({"type": "move", "node": 1, "x": 5, "y": 6, "z": 7})");
  EXPECT_TRUE(test::errors_until_end(v).empty());
  EXPECT_EQ(
      request(d.port(), http::verb::post, "/api/nodes/1/position", R"({"x": 4, "y": 6})").result(),
      http::status::ok);
  EXPECT_EQ(d.dashboard->control_refused(), 0U);
}

}  // namespace
}  // namespace rfsitl::monitor
