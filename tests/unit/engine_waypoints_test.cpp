// A scenario's waypoint paths, run through the engine: at a mobility update
// each node is exactly where its straight legs put it (closed form, no model
// code), and between updates it holds that position (the documented lag of
// at most speed x engine.mobility_update_s).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "engine_run.hpp"
#include "rfsitl/common/geodesy.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"

namespace rfsitl::testing {
namespace {

// Ticks of 1 ms, mobility updates every 100 ms: a run whose last tick starts
// at an update time ends with the positions of that instant (the engine copies
// positions for other threads after every update at most 20 ms apart).
const char* const kScenario = R"(
time: {mode: virtual, sample_rate_hz: 1e6, tick_samples: 1000, duration_s: 1}
engine: {threads: 1, stats_interval_s: 0, mobility_update_s: 0.1}
nodes:
  - id: 1
    mobility: {type: waypoints, loop: false, points: [{t: 0, x: 0, y: 0, z: 10}, {t: 10, x: 100, y: 0, z: 10}, {x: 100, y: 50, z: 10, speed_mps: 5}]}
  - id: 2
    mobility: {type: waypoints, points: [{lat: 43.0, lon: -78.79, alt: 30}, {lat: 43.001, lon: -78.79, alt: 30, speed_mps: 5}]}
)";
constexpr double kTick = 1e-3;
constexpr double kUpdate = 0.1;

// Node 1: 10 m/s east for 10 s, then 5 m/s north for 10 s, then still.
LocalPosition node1_at(double t) {
  if (t <= 10) return {10 * t, 0, 10};
  if (t <= 20) return {100, 5 * (t - 10), 10};
  return {100, 50, 10};
}

// Node 2: from A to B at 5 m/s. Local east/north/up is a rigid transform of
// ECEF, so a straight leg there is a straight leg in ECEF at the same speed.
Ecef node2_at(double t) {
  const Ecef a = geodetic_to_ecef({43.0, -78.79, 30});
  const Ecef b = geodetic_to_ecef({43.001, -78.79, 30});
  const double f = std::min(1.0, 5 * t / distance_m(a, b));
  return {a.x + f * (b.x - a.x), a.y + f * (b.y - a.y), a.z + f * (b.z - a.z)};
}

// Where the engine has both nodes after a run whose last tick starts at `t`.
std::vector<std::optional<Ecef>> positions_after(double t) {
  scenario::Scenario s = scenario::parse_scenario(kScenario, "waypoints.yaml");
  s.timing.duration_s = t + kTick / 2;
  return run_engine(s).engine->positions();
}

TEST(EngineWaypoints, NodesAreOnTheirLegsAtEachUpdate) {
  const scenario::Scenario s = scenario::parse_scenario(kScenario, "waypoints.yaml");
  const GeodeticPosition& origin = s.channel.origin;
  const double leg2_s =
      distance_m(geodetic_to_ecef({43.0, -78.79, 30}), geodetic_to_ecef({43.001, -78.79, 30})) / 5;
  ASSERT_NEAR(leg2_s, 22.2, 0.1);  // 0.001 degree of latitude is about 111 m
  for (const double t : {0.0, 2.5, 10.0, 14.2, 21.0, 23.0}) {
    SCOPED_TRACE("t = " + std::to_string(t));
    const auto p = positions_after(t);
    ASSERT_TRUE(p.at(0) && p.at(1));
    EXPECT_LT(distance_m(*p[0], local_to_ecef(node1_at(t), origin)), 1e-6);
    EXPECT_LT(distance_m(*p[1], node2_at(t)), 1e-6);
  }
}

TEST(EngineWaypoints, BetweenUpdatesANodeHoldsItsLastUpdatedPosition) {
  const scenario::Scenario s = scenario::parse_scenario(kScenario, "waypoints.yaml");
  const double t = 2.5 + kUpdate / 2;  // half an interval after the update at 2.5 s
  const auto p = positions_after(t);
  ASSERT_TRUE(p.at(0).has_value());
  const Ecef held = local_to_ecef(node1_at(2.5), s.channel.origin);
  EXPECT_LT(distance_m(*p[0], held), 1e-6);
  // Behind the path by the distance flown since, which the interval bounds.
  const double behind = distance_m(*p[0], local_to_ecef(node1_at(t), s.channel.origin));
  EXPECT_NEAR(behind, 10 * kUpdate / 2, 1e-6);
  EXPECT_LE(behind, 10 * kUpdate);
}

}  // namespace
}  // namespace rfsitl::testing
