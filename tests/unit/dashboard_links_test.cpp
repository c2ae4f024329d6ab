/// The dashboard's link table routes and HEAD: GET /api/links (what `rfsitl
/// links` reads), the per-link series of /metrics, and HEAD on every GET route.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <utility>

#include "dashboard_test_support.hpp"

namespace rfsitl::monitor {
namespace {

using namespace test;  // NOLINT(google-build-using-namespace): the support's Beast aliases

/// A HEAD request: its response's status and headers (Beast must be told
/// that no body follows the Content-Length of a HEAD response); `body_bytes`
/// receives what arrived after the headers before the server's next answer.
http::response<http::empty_body> head(std::uint16_t port, const std::string& target,
                                      std::size_t& body_bytes) {
  asio::io_context io;
  beast::tcp_stream stream(io);
  stream.expires_after(std::chrono::seconds(20));
  stream.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
  http::request<http::empty_body> req{http::verb::head, target, 11};
  req.set(http::field::host, "127.0.0.1:" + std::to_string(port));
  http::write(stream, req);
  beast::flat_buffer buffer;
  http::response_parser<http::empty_body> parser;
  parser.skip(true);
  http::read_header(stream, buffer, parser);
  // A body sent after the headers would precede the answer to this GET.
  http::request<http::empty_body> next{http::verb::get, "/api/stats", 11};
  next.set(http::field::host, "127.0.0.1:" + std::to_string(port));
  http::write(stream, next);
  http::response<http::string_body> second;
  http::read(stream, buffer, second);
  EXPECT_EQ(second.result(), http::status::ok) << "the HEAD response carried bytes after it";
  body_bytes = buffer.size();
  return parser.release();
}

TEST(DashboardLinks, HeadAnswersEveryGetRouteWithItsHeadersAndNoBody) {
  LiveDashboard d;
  for (const char* target : {"/", "/api/stats", "/api/snapshot", "/api/links", "/metrics"}) {
    const auto got = request(d.port(), http::verb::get, target);
    ASSERT_EQ(got.result(), http::status::ok) << target;
    std::size_t extra = 0;
    const auto res = head(d.port(), target, extra);
    EXPECT_EQ(res.result(), http::status::ok) << target;
    EXPECT_EQ(res[http::field::content_type], got[http::field::content_type]) << target;
    // The length GET would send (the page's exactly; live documents vary).
    const std::string length(res[http::field::content_length]);
    ASSERT_FALSE(length.empty()) << target;
    EXPECT_GT(std::stoul(length), 0U) << target;
    if (std::string(target) == "/") {
      EXPECT_EQ(std::stoul(length), got.body().size());
    }
    EXPECT_EQ(extra, 0U) << target;
  }
  std::size_t extra = 0;
  EXPECT_EQ(head(d.port(), "/no-such-page", extra).result(), http::status::not_found);
  // Other methods still are not allowed, and say which are.
  const auto put = request(d.port(), http::verb::put, "/metrics");
  EXPECT_EQ(put.result(), http::status::method_not_allowed);
  EXPECT_EQ(put[http::field::allow], "GET, HEAD");
}

TEST(DashboardLinks, ApiLinksServesEveryOrderedPairAndRefusesBadQueries) {
  LiveDashboard d;
  const auto res = request(d.port(), http::verb::get, "/api/links?payload=120");
  ASSERT_EQ(res.result(), http::status::ok) << res.body();
  const auto doc = nlohmann::json::parse(res.body());
  EXPECT_EQ(doc.at("nodes"), 2);
  EXPECT_EQ(doc.at("payload_bytes"), 120);
  ASSERT_EQ(doc.at("links").size(), 2U);
  std::set<std::pair<int, int>> pairs;
  for (const auto& l : doc.at("links")) pairs.emplace(l.at("tx"), l.at("rx"));
  EXPECT_EQ(pairs, (std::set<std::pair<int, int>>{{1, 2}, {2, 1}}));
  const auto top =
      nlohmann::json::parse(request(d.port(), http::verb::get, "/api/links?top=1").body());
  EXPECT_EQ(top.at("links").size(), 1U);
  const auto bad = request(d.port(), http::verb::get, "/api/links?top=1&worst=1");
  EXPECT_EQ(bad.result(), http::status::bad_request);
  EXPECT_NE(bad.body().find("exclude each other"), std::string::npos) << bad.body();
}

TEST(DashboardLinks, MetricsCarryEachLinksFrameSeries) {
  LiveDashboard d;
  const std::string text = request(d.port(), http::verb::get, "/metrics").body();
  for (const char* series :
       {"rfsitl_link_frames_total{tx=\"1\",rx=\"2\",outcome=\"received\"} 0\n",
        "rfsitl_link_frames_total{tx=\"2\",rx=\"1\",outcome=\"lost\"} 0\n",
        "# TYPE rfsitl_link_snr_db gauge\n", "# TYPE rfsitl_link_frames_total counter\n"}) {
    EXPECT_NE(text.find(series), std::string::npos) << series << "\n" << text;
  }
}

}  // namespace
}  // namespace rfsitl::monitor
