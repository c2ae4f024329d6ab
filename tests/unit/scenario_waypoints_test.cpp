// `mobility: {type: waypoints, points: [...]}` in a scenario file: both forms
// of a point are read as the model's list setting, and every mistake inside
// the list names the node, the item, the field and the item's own line.
#include <gtest/gtest.h>

#include <string>

#include "rfsitl/scenario/scenario_loader.hpp"
#include "scenario_errors.hpp"

namespace rfsitl::scenario {
namespace {

// A one-node scenario whose node's mobility is `mobility` (lines 3 on).
std::string node_with(const std::string& mobility) {
  return "nodes:\n  - id: 1\n    mobility:\n" + mobility;
}

TEST(ScenarioWaypoints, BothFormsAreReadAsTheModelsPoints) {
  const Scenario s = parse_scenario(
      "nodes:\n"
      "  - id: 1\n"
      "    mobility: {type: waypoints, loop: false, points: [{t: 0, x: 0, y: 0, z: 10}, "
      "{t: 10, x: 100, y: 0, z: 10}]}\n"
      "  - id: 2\n"
      "    mobility:\n"
      "      type: waypoints\n"
      "      points:\n"
      "        - {lat: 43.0, lon: -78.79, alt: 30}\n"
      "        - lat: 43.001\n"
      "          lon: -78.79\n"
      "          speed_mps: 5\n"
      "          dwell_s: 2\n",
      "t.yaml");
  ASSERT_TRUE(s.nodes[0].mobility && s.nodes[1].mobility);
  EXPECT_EQ(s.nodes[0].mobility->type, "waypoints");
  EXPECT_FALSE(s.nodes[0].mobility->settings.get<bool>("loop"));
  using config::Record;
  EXPECT_EQ(s.nodes[0].mobility->settings.get<config::Records>("points"),
            (config::Records{Record{{"t", 0}, {"x", 0}, {"y", 0}, {"z", 10}},
                             Record{{"t", 10}, {"x", 100}, {"y", 0}, {"z", 10}}}));
  EXPECT_EQ(s.nodes[1].mobility->settings.get<config::Records>("points"),
            (config::Records{
                Record{{"lat", 43.0}, {"lon", -78.79}, {"alt", 30}},
                Record{{"lat", 43.001}, {"lon", -78.79}, {"speed_mps", 5}, {"dwell_s", 2}}}));
  validate_scenario(s);  // what the loader accepts, the checks after overrides accept
}

TEST(ScenarioWaypoints, AFieldOutOfRangeNamesItsItemAndLine) {
  EXPECT_EQ(parse_error_of(node_with("      type: waypoints\n"
                                     "      points:\n"
                                     "        - {t: 0, x: 0, y: 0}\n"
                                     "        - {t: 5, x: 1, y: 0}\n"
                                     "        - {t: -3, x: 5, y: 0}\n")),
            "t.yaml:8: nodes[0].mobility.points[2].t: must be >= 0, got -3");
  // A block mapping item: the field's own line.
  EXPECT_EQ(parse_error_of(node_with("      type: waypoints\n"
                                     "      points:\n"
                                     "        - x: 0\n"
                                     "          y: 0\n"
                                     "          lat: 91\n")),
            "t.yaml:8: nodes[0].mobility.points[0].lat: must be in [-90, 90], got 91");
  EXPECT_EQ(parse_error_of(node_with("      type: waypoints\n"
                                     "      points: [{x: 0, y: 0}, {x: 9, y: 0, speed_mps: 0}]\n")),
            "t.yaml:5: nodes[0].mobility.points[1].speed_mps: must be in (0, 10000], got 0");
  EXPECT_EQ(parse_error_of(node_with("      type: waypoints\n"
                                     "      points: [{x: 0, y: 0, t: \"3\"}]\n")),
            "t.yaml:5: nodes[0].mobility.points[0].t: expected a number, got the string \"3\"");
}

TEST(ScenarioWaypoints, ItemsWithUnknownConflictingOrMissingFieldsAreRefused) {
  const std::string head = "      type: waypoints\n      points:\n        - {x: 0, y: 0}\n";
  EXPECT_EQ(parse_error_of(node_with(head + "        - {x: 5, y: 0, tt: 3}\n")),
            "t.yaml:7: nodes[0].mobility.points[1].tt: unknown key (allowed in "
            "nodes[0].mobility.points[1]: t, x, y, z, lat, lon, alt, speed_mps, dwell_s)");
  EXPECT_EQ(parse_error_of(node_with(head + "        - x: 5\n"
                                            "          y: 0\n"
                                            "          t: 3\n"
                                            "          speed_mps: 2\n")),
            "t.yaml:10: nodes[0].mobility.points[1].speed_mps: conflicts with t; give the "
            "arrival time or the leg's speed");
  EXPECT_EQ(parse_error_of(node_with(head + "        - {x: 5, y: 0}\n")),
            "t.yaml:7: nodes[0].mobility.points[1]: needs t (arrival time) or speed_mps (the "
            "leg's speed)");
  EXPECT_EQ(parse_error_of(node_with(head + "        - {t: 3, z: 5}\n")),
            "t.yaml:7: nodes[0].mobility.points[1]: needs x and y (z defaults to 0) or lat and "
            "lon (alt defaults to 0)");
  EXPECT_EQ(parse_error_of(node_with(head + "        - {t: 3, lat: 43}\n")),
            "t.yaml:7: nodes[0].mobility.points[1]: needs x and y (z defaults to 0) or lat and "
            "lon (alt defaults to 0)");
  EXPECT_EQ(parse_error_of(node_with(head + "        - {t: 3, x: 5, y: 0, lat: 43, lon: -78}\n")),
            "t.yaml:7: nodes[0].mobility.points[1]: mixes lat/lon/alt with x/y/z; use one form");
  // An empty item (yaml-cpp marks it at the next token, so only the key is checked).
  EXPECT_NE(parse_error_of(node_with(head + "        -\n"))
                .find(": nodes[0].mobility.points[1]: needs x and y"),
            std::string::npos);
  EXPECT_EQ(parse_error_of(node_with(head + "        - 5\n")),
            "t.yaml:7: nodes[0].mobility.points[1]: expected a mapping (key: value), got '5'");
  EXPECT_EQ(parse_error_of(node_with("      type: waypoints\n"
                                     "      points: [{x: 0, y: 0, speed_mps: 3}]\n")),
            "t.yaml:5: nodes[0].mobility.points[0].speed_mps: not allowed on the first point: "
            "no leg arrives at it");
}

TEST(ScenarioWaypoints, TheListItselfMustBeANonEmptyList) {
  EXPECT_EQ(parse_error_of(node_with("      type: waypoints\n      points: []\n")),
            "t.yaml:5: nodes[0].mobility.points: must hold at least 1 item, got 0");
  EXPECT_EQ(parse_error_of(node_with("      type: waypoints\n      points:\n")),
            "t.yaml:5: nodes[0].mobility.points: must hold at least 1 item, got 0");
  EXPECT_EQ(parse_error_of(node_with("      type: waypoints\n")),
            "t.yaml:3: nodes[0].mobility.points: must hold at least 1 item, got 0");
  EXPECT_EQ(parse_error_of(node_with("      type: waypoints\n      points: 5\n")),
            "t.yaml:5: nodes[0].mobility.points: expected a list, got '5'");
  EXPECT_EQ(parse_error_of(node_with("      type: waypoints\n      points: {x: 0, y: 0}\n")),
            "t.yaml:5: nodes[0].mobility.points: expected a list, got a mapping");
}

TEST(ScenarioWaypoints, ThePathsOwnRulesNameTheirLineAtLoadTime) {
  // Times out of order, by time and through a speed leg (10 m at 1 m/s: arrives at 12).
  EXPECT_EQ(parse_error_of(node_with("      type: waypoints\n"
                                     "      points:\n"
                                     "        - {t: 10, x: 0, y: 0}\n"
                                     "        - {t: 5, x: 10, y: 0}\n")),
            "t.yaml:7: nodes[0].mobility.points[1].t: must not be before the departure from the "
            "previous point at 10 s (got 5)");
  EXPECT_EQ(parse_error_of(node_with("      type: waypoints\n"
                                     "      points:\n"
                                     "        - {t: 2, x: 0, y: 0}\n"
                                     "        - {speed_mps: 1, x: 10, y: 0}\n"
                                     "        - {t: 11, x: 10, y: 5}\n")),
            "t.yaml:8: nodes[0].mobility.points[2].t: must not be before the departure from the "
            "previous point at 12 s (got 11)");
  // The same for lat/lon points: 0.001 degree of latitude is about 111 m (22 s at 5 m/s).
  EXPECT_NE(parse_error_of(node_with("      type: waypoints\n"
                                     "      points:\n"
                                     "        - {lat: 43.0, lon: -78.79}\n"
                                     "        - {lat: 43.001, lon: -78.79, speed_mps: 5}\n"
                                     "        - {lat: 43.001, lon: -78.789, t: 20}\n"))
                .find("t.yaml:8: nodes[0].mobility.points[2].t: must not be before the "
                      "departure from the previous point at 22.2"),
            std::string::npos);
  EXPECT_EQ(parse_error_of(node_with("      type: waypoints\n"
                                     "      loop: true\n"
                                     "      points: [{x: 0, y: 0}, {t: 10, x: 100, y: 0}]\n")),
            "t.yaml:5: nodes[0].mobility.loop: the last point must be the first one (a closed "
            "path), 100 m away");
}

}  // namespace
}  // namespace rfsitl::scenario
