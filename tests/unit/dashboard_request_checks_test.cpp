// The dashboard answers only requests that name it (Host) and come from its
// own page or from no page at all (Origin): DNS rebinding and cross-site
// requests are refused.
#include "rfsitl/monitor/request_checks.hpp"

#include <gtest/gtest.h>

#include "dashboard_test_support.hpp"
#include "log_capture.hpp"

namespace rfsitl::monitor {
namespace {

namespace http = test::http;
using test::LiveDashboard;
using test::request;
using test::Viewer;

TEST(DashboardRequestChecks, HostMustBeALoopbackNameOrTheBindAddressOnThisPort) {
  EXPECT_TRUE(host_allowed("127.0.0.1:15700", "127.0.0.1", 15700));
  EXPECT_TRUE(host_allowed("127.0.0.1", "127.0.0.1", 15700));  // without the port
  EXPECT_TRUE(host_allowed("localhost:15700", "127.0.0.1", 15700));
  EXPECT_TRUE(host_allowed("LocalHost", "127.0.0.1", 15700));
  EXPECT_TRUE(host_allowed("[::1]:15700", "127.0.0.1", 15700));
  EXPECT_TRUE(host_allowed("[::1]", "::1", 15700));
  EXPECT_TRUE(host_allowed("192.168.1.5:15700", "192.168.1.5", 15700));  // --bind
  EXPECT_TRUE(
      host_allowed("10.0.0.7:15700", "0.0.0.0", 15700));  // any IP literal when bound to all
  EXPECT_TRUE(host_allowed("[fe80::2]:15700", "::", 15700));

  EXPECT_FALSE(host_allowed("evil.example:15700", "127.0.0.1", 15700));  // DNS rebinding
  EXPECT_FALSE(host_allowed("evil.example:15700", "0.0.0.0", 15700));    // a name, even then
  EXPECT_FALSE(host_allowed("localhost.evil.example", "127.0.0.1", 15700));
  EXPECT_FALSE(host_allowed("127.0.0.1:15701", "127.0.0.1", 15700));  // another port
  EXPECT_FALSE(host_allowed("192.168.1.5:15700", "127.0.0.1", 15700));
  EXPECT_FALSE(host_allowed("", "127.0.0.1", 15700));
  EXPECT_FALSE(host_allowed("127.0.0.1:", "127.0.0.1", 15700));
  EXPECT_FALSE(host_allowed("::1", "127.0.0.1", 15700));  // unbracketed
  EXPECT_FALSE(host_allowed("[::1", "127.0.0.1", 15700));
}

TEST(DashboardRequestChecks, OriginMustBeTheDashboardsOwnPage) {
  EXPECT_TRUE(origin_allowed("http://127.0.0.1:15700", "127.0.0.1", 15700));
  EXPECT_TRUE(origin_allowed("http://localhost:15700", "127.0.0.1", 15700));
  EXPECT_TRUE(origin_allowed("http://[::1]:15700", "::1", 15700));
  EXPECT_TRUE(origin_allowed("http://localhost", "127.0.0.1", 80));

  EXPECT_FALSE(origin_allowed("http://evil.example:15700", "127.0.0.1", 15700));
  EXPECT_FALSE(origin_allowed("http://localhost:8080", "127.0.0.1", 15700));  // another local app
  EXPECT_FALSE(origin_allowed("http://localhost", "127.0.0.1", 15700));       // port 80
  EXPECT_FALSE(origin_allowed("https://127.0.0.1:15700", "127.0.0.1", 15700));
  EXPECT_FALSE(origin_allowed("null", "127.0.0.1", 15700));
  EXPECT_FALSE(origin_allowed("", "127.0.0.1", 15700));

  bool misdirected = false;
  EXPECT_EQ(request_refusal("127.0.0.1:80", std::nullopt, "127.0.0.1", 80, misdirected), "");
  EXPECT_NE(request_refusal(std::nullopt, std::nullopt, "127.0.0.1", 80, misdirected), "");
  EXPECT_TRUE(misdirected);
  const std::string why =
      request_refusal("127.0.0.1:80", "http://evil.example", "127.0.0.1", 80, misdirected);
  EXPECT_FALSE(misdirected);
  EXPECT_NE(why.find("http://evil.example"), std::string::npos) << why;
}

TEST(DashboardRequestChecks, ServerRefusesAForeignHostWith421AndServesLoopbackNames) {
  LiveDashboard d;
  const auto port = d.port();
  const std::string p = ":" + std::to_string(port);
  for (const std::string& host :
       std::vector<std::string>{"127.0.0.1" + p, "localhost" + p, "[::1]" + p, "127.0.0.1"}) {
    const auto res = request(port, http::verb::get, "/api/stats", "", {{http::field::host, host}});
    EXPECT_EQ(res.result(), http::status::ok) << host << ": " << res.body();
  }
  // The page of evil.example, its name rebound to 127.0.0.1, reading the stats.
  for (const std::string target : {"/api/stats", "/metrics", "/", "/api/snapshot"}) {
    const auto res =
        request(port, http::verb::get, target, "", {{http::field::host, "evil.example" + p}});
    EXPECT_EQ(res.result(), http::status::misdirected_request) << target;
    EXPECT_NE(res.body().find("DNS rebinding"), std::string::npos) << res.body();
    EXPECT_EQ(res.body().find("\"nodes\""), std::string::npos) << "leaked: " << res.body();
  }
  const auto no_host = request(port, http::verb::get, "/api/stats", "", {{http::field::host, ""}});
  EXPECT_EQ(no_host.result(), http::status::misdirected_request);
}

TEST(DashboardRequestChecks, ServerRefusesCrossSitePostsAndWebSockets) {
  DashboardSettings settings;
  settings.control = true;
  LiveDashboard d(settings);
  const auto port = d.port();
  const std::string p = ":" + std::to_string(port);
  const auto post = request(port, http::verb::post, "/api/nodes/1/position", R"({"x":1,"y":2})",
                            {{http::field::origin, "http://evil.example"}});
  EXPECT_EQ(post.result(), http::status::forbidden) << post.body();

  {  // The dashboard's own page.
    Viewer v;
    const auto ec = v.connect(port, {{http::field::origin, "http://127.0.0.1" + p}});
    ASSERT_FALSE(ec) << ec.message();
    EXPECT_NE(v.read().find("\"hello\""), std::string::npos);
  }
  {  // A script: no Origin.
    Viewer v;
    const auto ec = v.connect(port);
    EXPECT_FALSE(ec) << ec.message();
  }
  // The refusals, seen by a WebSocket client and as plain HTTP.
  const test::Headers upgrade = {{http::field::upgrade, "websocket"},
                                 {http::field::connection, "Upgrade"},
                                 {http::field::sec_websocket_key, "dGhlIHNhbXBsZSBub25jZQ=="},
                                 {http::field::sec_websocket_version, "13"}};
  const auto refused = [&](const test::Headers& extra, http::status expected) {
    test::Viewer v;
    EXPECT_TRUE(v.connect(port, extra));
    test::Headers headers = upgrade;
    for (const auto& [field, value] : extra) headers[field] = value;
    const auto res = request(port, http::verb::get, "/ws", "", headers);
    EXPECT_EQ(res.result(), expected) << res.body();
    EXPECT_NE(res.body().find("refused"), std::string::npos) << res.body();
  };
  refused({{http::field::origin, "http://evil.example"}}, http::status::forbidden);
  // DNS rebinding: Host and Origin agree, but name evil.example.
  refused(
      {{http::field::host, "evil.example" + p}, {http::field::origin, "http://evil.example" + p}},
      http::status::misdirected_request);
  // Another local web app's page (another port).
  refused({{http::field::origin, "http://localhost:8080"}}, http::status::forbidden);
  EXPECT_TRUE(test::wait_for([&] { return d.dashboard->viewers() == 0; }));
}

TEST(DashboardRequestChecks, RefusalsQuoteTheClientsHeaderEscapedInTheLog) {
  LiveDashboard d;
  ::rfsitl::testing::LogCapture log;
  // HTTP allows any byte from 0x80 up in a header value; 0x9b alone is the
  // 8-bit CSI that starts a terminal escape sequence.
  const std::string origin = std::string("http://evil.example\x9b") + "2J";
  const auto res =
      request(d.port(), http::verb::get, "/api/stats", "", {{http::field::origin, origin}});
  EXPECT_EQ(res.result(), http::status::forbidden) << res.body();
  const auto lines = log.lines_with("dashboard: GET /api/stats refused");
  ASSERT_EQ(lines.size(), 1U);
  EXPECT_NE(lines[0].find("http://evil.example\\x9b2J"), std::string::npos) << lines[0];
  EXPECT_EQ(lines[0].find('\x9b'), std::string::npos) << lines[0];
}

}  // namespace
}  // namespace rfsitl::monitor
