// Moving a node from the dashboard (POST /api/nodes/ID/position and the
// WebSocket "move") accepts exactly what the location port accepts, and
// refuses in our own words.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "dashboard_test_support.hpp"
#include "rfsitl/common/geodesy.hpp"
#include "rfsitl/monitor/position_request.hpp"
#include "rfsitl/position/location_port/location_line.hpp"

namespace rfsitl::monitor {
namespace {

namespace http = test::http;
using test::LiveDashboard;
using test::request;
using Json = nlohmann::json;

/// POSTs `body` for node 1; the status and the error text ("" on success).
std::pair<http::status, std::string> post(const LiveDashboard& d, const std::string& body) {
  const auto res = request(d.port(), http::verb::post, "/api/nodes/1/position", body);
  const Json j = Json::parse(res.body(), nullptr, false);
  return {res.result(), j.is_object() && j.contains("error") ? j["error"].get<std::string>() : ""};
}

TEST(DashboardPosition, PostRefusesWhatTheLocationPortRefusesAndAppliesTheRest) {
  DashboardSettings settings;
  settings.control = true;
  LiveDashboard d(settings);
  EXPECT_EQ(post(d, R"({"x": 5, "y": 6, "z": 7})").first, http::status::ok);
  // The same bodies the location port refuses, with the same reason.
  for (const std::string body :
       {R"({"x": 0, "y": 0, "z": 500000})", R"({"x": 0, "y": 0, "z": -50000})",
        R"({"lat": 91, "lon": 0, "alt": 0})", R"({"lat": 10, "lon": -180.5})",
        R"({"lat": 10, "lon": 10, "alt": 100001})", R"({"x": 1.7e308, "y": 0})",
        R"({"x": 0, "y": -10000000.5, "z": 0})"}) {
    const auto [status, error] = post(d, body);
    EXPECT_EQ(status, http::status::bad_request) << body;
    const auto port = position::parse_location_line(body);
    ASSERT_FALSE(port.error.empty()) << body;
    EXPECT_EQ(error, "bad position: " + port.error) << body;
  }
  EXPECT_EQ(post(d, R"({"x": 0, "y": 0, "z": 500000})").second,
            "bad position: z 500000 out of range [-1000, 100000]");
  EXPECT_EQ(post(d, R"({"x": 1.7e308, "y": 0})").second,
            "bad position: x 1.7e+308 out of range [-10000000, 10000000]");
  // Run a few ticks: node 1 stands where the one accepted request put it.
  const std::atomic<bool> stop{false};
  d.engine->run(stop);
  const auto where = d.engine->positions().at(0);
  ASSERT_TRUE(where.has_value());
  const LocalPosition l = ecef_to_local(*where, d.s.channel.origin);
  EXPECT_NEAR(l.x_m, 5.0, 1e-6);
  EXPECT_NEAR(l.y_m, 6.0, 1e-6);
  EXPECT_NEAR(l.z_m, 7.0, 1e-6);
}

TEST(DashboardPosition, BadBodiesGetOurOwnWordsNamingTheField) {
  DashboardSettings settings;
  settings.control = true;
  LiveDashboard d(settings);
  const std::pair<std::string, std::string> cases[] = {
      {R"({"x": "a", "y": 0})", "bad position: x: expected a number"},
      {R"({"x": 1, "y": null})", "bad position: y: expected a number"},
      {R"({"x": 1, "y": 2, "z": [3]})", "bad position: z: expected a number"},
      {R"({"lat": true, "lon": 2})", "bad position: lat: expected a number"},
      {R"({"y": 2})", "bad position: x: missing (expected a number)"},
      {R"({"lat": 1, "lon": 2, "z": 3})",
       "bad position: mixes lat/lon/alt with x/y/z: use one or the other"},
      {R"([1, 2, 3])", "bad position: expected a JSON object with x, y[, z] or lat, lon[, alt]"},
      {R"({"speed": 3})",
       "bad position: no position: expected x, y[, z] (metres) or lat, lon[, alt]"},
  };
  for (const auto& [body, expected] : cases) {
    const auto [status, error] = post(d, body);
    EXPECT_EQ(status, http::status::bad_request) << body;
    EXPECT_EQ(error, expected) << body;
    EXPECT_EQ(error.find("json.exception"), std::string::npos) << error;
  }
  const auto [status, error] = post(d, "{not json");
  EXPECT_EQ(status, http::status::bad_request);
  EXPECT_EQ(error.rfind("body is not JSON", 0), 0U) << error;
}

TEST(DashboardPosition, WebSocketMoveAppliesTheSameLimits) {
  DashboardSettings settings;
  settings.control = true;
  LiveDashboard d(settings);
  test::Viewer v;
  const auto ec = v.connect(d.port());
  ASSERT_FALSE(ec) << ec.message();
  v.write(R"({"type": "move", "node": 2, "x": 0, "y": 0, "z": 500000})");
  v.write(R"({"type": "move", "node": 2, "x": "east", "y": 0})");
  const std::vector<std::string> errors = test::errors_until_end(v);
  EXPECT_EQ(errors, (std::vector<std::string>{"bad position: z 500000 out of range [-1000, 100000]",
                                              "bad position: x: expected a number"}));
}

TEST(DashboardPosition, MissingHeightKeepsTheDefaultGiven) {
  const auto local = read_position_request(Json{{"x", 1}, {"y", 2}}, 33.0, 44.0);
  ASSERT_TRUE(local.position) << local.error;
  EXPECT_EQ(std::get<LocalPosition>(*local.position).z_m, 33.0);
  const auto geo = read_position_request(Json{{"lat", 1}, {"lon", 2}, {"node", 3}}, 33.0, 44.0);
  ASSERT_TRUE(geo.position) << geo.error;
  EXPECT_EQ(std::get<GeodeticPosition>(*geo.position).alt_m, 44.0);
}

}  // namespace
}  // namespace rfsitl::monitor

namespace rfsitl::monitor {
namespace {

// Issue 15 W8: ids are compared at full width, so 2^32 + 1 is no node, not node 1.
TEST(DashboardPosition, NodeIdsDoNotAliasModulo2To32) {
  DashboardSettings settings;
  settings.control = true;
  LiveDashboard d(settings);
  for (const std::string id : {"4294967297", "18446744073709551617", "-1", "%201", "1x", ""}) {
    const auto res = test::request(d.port(), http::verb::post, "/api/nodes/" + id + "/position",
                                   R"({"x": 5, "y": 6, "z": 7})");
    EXPECT_NE(res.result(), http::status::ok) << "'" << id << "'";
  }
  test::Viewer v;
  ASSERT_FALSE(v.connect(d.port()));
  v.write(R"({"type": "move", "node": 4294967297, "x": 5, "y": 6, "z": 7})");
  const std::vector<std::string> errors = test::errors_until_end(v);
  ASSERT_EQ(errors.size(), 1U);
  // Node 1 never moved from its scenario position.
  const std::atomic<bool> stop{false};
  d.engine->run(stop);
  const auto where = d.engine->positions().at(0);
  ASSERT_TRUE(where.has_value());
  EXPECT_GT(std::abs(ecef_to_local(*where, d.s.channel.origin).x_m - 5.0), 0.5);
}

}  // namespace
}  // namespace rfsitl::monitor
