// Waypoint paths: timed and speed-given legs, dwell, loops, WGS84 points, and
// the settings they refuse.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "mobility_test_support.hpp"
#include "rfsitl/position/mobility/local_frame.hpp"
#include "rfsitl/position/mobility/waypoint_model.hpp"

namespace rfsitl::position::mobility {
namespace {

using testing::near;
using testing::velocity_is_derivative;
const GeodeticPosition kOrigin{43.0008, -78.789, 180.0};

Waypoint at(double x, double y, double z, double t, double dwell = 0) {
  return {LocalPosition{x, y, z}, t, std::nullopt, dwell};
}
Waypoint by_speed(double x, double y, double z, double v, double dwell = 0) {
  return {LocalPosition{x, y, z}, std::nullopt, v, dwell};
}

TEST(MobilityWaypoints, TimedLegsAreStraightAndHoldTheirEnds) {
  WaypointModel m({{at(0, 0, 0, 10), at(100, 0, 0, 20), at(100, 50, 10, 30)}}, kOrigin);
  EXPECT_TRUE(near(m.state_at(-1).position, {0, 0, 0}));  // before the first time
  EXPECT_TRUE(near(m.state_at(5).velocity, {0, 0, 0}, 0.0));
  EXPECT_TRUE(near(m.state_at(10).position, {0, 0, 0}));
  EXPECT_TRUE(near(m.state_at(10).velocity, {10, 0, 0}));  // the leg starting here
  EXPECT_TRUE(near(m.state_at(12.5).position, {25, 0, 0}));
  EXPECT_TRUE(near(m.state_at(20).position, {100, 0, 0}));
  EXPECT_TRUE(near(m.state_at(26).position, {100, 30, 6}));
  EXPECT_TRUE(near(m.state_at(26).velocity, {0, 5, 1}));
  EXPECT_TRUE(near(m.state_at(30).position, {100, 50, 10}));
  EXPECT_TRUE(near(m.state_at(1e6).position, {100, 50, 10}));  // after the last
  EXPECT_TRUE(near(m.state_at(1e6).velocity, {0, 0, 0}, 0.0));
  // Asked out of order, the answers are the same.
  EXPECT_TRUE(near(m.state_at(12.5).position, {25, 0, 0}));
  for (double t = 10.3; t < 30; t += 1.1) EXPECT_TRUE(velocity_is_derivative(m, t));
}

TEST(MobilityWaypoints, SpeedsGiveTheTimesAndDwellHolds) {
  // 50 m at 5 m/s: 10 s; dwell 2 s; 120 m up at 12 m/s: 10 s.
  WaypointModel m({{at(0, 0, 0, 3), by_speed(30, 40, 0, 5, 2), by_speed(30, 40, 120, 12)}},
                  kOrigin);
  EXPECT_TRUE(near(m.state_at(8).position, {15, 20, 0}));
  EXPECT_TRUE(near(m.state_at(8).velocity, {3, 4, 0}));
  EXPECT_TRUE(near(m.state_at(13).position, {30, 40, 0}));
  EXPECT_TRUE(near(m.state_at(14).position, {30, 40, 0}));  // dwelling
  EXPECT_TRUE(near(m.state_at(14).velocity, {0, 0, 0}, 0.0));
  EXPECT_TRUE(near(m.state_at(15).velocity, {0, 0, 12}));  // leaves at 13 + 2
  EXPECT_TRUE(near(m.state_at(20).position, {30, 40, 60}));
  EXPECT_TRUE(near(m.state_at(25).position, {30, 40, 120}));
  EXPECT_DOUBLE_EQ(m.track().end_s(), 25.0);
}

TEST(MobilityWaypoints, ALoopRepeatsTheClosedPathWithItsPeriod) {
  // A 100 m square at 10 m/s: 40 s a lap, plus 5 s of dwell at the start.
  WaypointModel m({{at(0, 0, 50, 0, 5), by_speed(100, 0, 50, 10), by_speed(100, 100, 50, 10),
                    by_speed(0, 100, 50, 10), by_speed(0, 0, 50, 10)},
                   true},
                  kOrigin);
  EXPECT_DOUBLE_EQ(m.period_s(), 45.0);
  for (int lap = 0; lap < 1000; lap += 111) {
    const double t0 = 45.0 * lap;
    EXPECT_TRUE(near(m.state_at(t0 + 2).position, {0, 0, 50}));  // dwelling
    EXPECT_TRUE(near(m.state_at(t0 + 10).position, {50, 0, 50}));
    EXPECT_TRUE(near(m.state_at(t0 + 10).velocity, {10, 0, 0}));
    EXPECT_TRUE(near(m.state_at(t0 + 20).position, {100, 50, 50}));
    EXPECT_TRUE(near(m.state_at(t0 + 33).position, {20, 100, 50}));
    EXPECT_TRUE(near(m.state_at(t0 + 44).position, {0, 10, 50}));
    EXPECT_TRUE(near(m.state_at(t0 + 44).velocity, {0, -10, 0}));
    EXPECT_TRUE(velocity_is_derivative(m, t0 + 27.7));
  }
}

TEST(MobilityWaypoints, ATimedLoopKeepsItsTimesFromTheFirstPoint) {
  WaypointModel m({{at(0, 0, 0, 100), at(60, 0, 0, 106), at(0, 0, 0, 112)}, true}, kOrigin);
  EXPECT_DOUBLE_EQ(m.period_s(), 12.0);
  EXPECT_TRUE(near(m.state_at(50).position, {0, 0, 0}));  // before the first time: no loop
  EXPECT_TRUE(near(m.state_at(103).position, {30, 0, 0}));
  EXPECT_TRUE(near(m.state_at(103 + 12 * 7).position, {30, 0, 0}));
  EXPECT_TRUE(near(m.state_at(109 + 12 * 7).position, {30, 0, 0}));
  EXPECT_TRUE(near(m.state_at(109 + 12 * 7).velocity, {-10, 0, 0}));
}

TEST(MobilityWaypoints, Wgs84PointsAreInterpolatedInLocalEnu) {
  const GeodeticPosition a{43.0008, -78.789, 200.0};
  const GeodeticPosition b{43.0050, -78.780, 260.0};
  WaypointModel m({{{a, 0.0, std::nullopt, 0.0}, {b, 100.0, std::nullopt, 0.0}}}, kOrigin);
  const LocalPosition la = to_local(a, kOrigin);
  const LocalPosition lb = to_local(b, kOrigin);
  EXPECT_TRUE(near(m.state_at(0).position, la, 1e-9));
  EXPECT_TRUE(near(m.state_at(100).position, lb, 1e-9));
  EXPECT_TRUE(
      near(m.state_at(25).position, {la.x_m + (lb.x_m - la.x_m) / 4, la.y_m + (lb.y_m - la.y_m) / 4,
                                     la.z_m + (lb.z_m - la.z_m) / 4}));
  EXPECT_NEAR(la.z_m, 20.0, 1e-3);  // 20 m above the origin's altitude, right over it
}

std::string refusal(const WaypointSettings& s) {
  try {
    WaypointModel m(s, kOrigin);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

TEST(MobilityWaypoints, RefusalsNameThePointAndField) {
  EXPECT_EQ(refusal({}), "waypoints.points must hold at least one point");
  EXPECT_EQ(refusal({{at(0, 0, 0, 0), by_speed(1, 0, 0, 0)}}),
            "waypoints.points[1].speed_mps must be > 0 and finite (got 0)");
  EXPECT_EQ(refusal({{by_speed(0, 0, 0, 3)}}),
            "waypoints.points[0].speed_mps is not allowed: no leg arrives at the first point");
  EXPECT_EQ(refusal({{at(0, 0, 0, 0), {LocalPosition{1, 0, 0}, 5.0, 2.0, 0.0}}}),
            "waypoints.points[1].time_s/speed_mps: exactly one must be set");
  EXPECT_EQ(refusal({{at(0, 0, 0, 0, 10), at(5, 0, 0, 8)}}),
            "waypoints.points[1].time_s must not be before the departure from the previous "
            "point at 10 s (got 8)");
  EXPECT_EQ(
      refusal({{at(0, 0, 0, 4), at(5, 0, 0, 4)}}),
      "waypoints.points[1].time_s leaves no time for the leg from the previous point (got 4)");
  EXPECT_EQ(refusal({{at(0, 0, 0, 0, -1)}}),
            "waypoints.points[0].dwell_s must be >= 0 and finite (got -1)");
  EXPECT_EQ(refusal({{at(0, 0, 0, 0), at(5, 0, 0, 1)}, true}),
            "waypoints.loop: the last point must be the first one (a closed path), 5 m away");
  EXPECT_EQ(refusal({{at(0, 0, 0, 0)}, true}),
            "waypoints.loop needs a path that takes time: period (got 0)");
  EXPECT_EQ(refusal({{{GeodeticPosition{43, 200, 0}, 0.0, std::nullopt, 0.0}}}),
            "waypoints.points[0].point: longitude 200 out of range [-180, 180]");
  // Two timed points at one place and one time are a harmless repeat.
  EXPECT_EQ(refusal({{at(1, 2, 3, 4), at(1, 2, 3, 4)}}), "accepted");
}

}  // namespace
}  // namespace rfsitl::position::mobility
