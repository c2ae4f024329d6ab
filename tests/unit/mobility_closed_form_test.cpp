// The closed-form models: a static node and an orbit, against their formulas.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "mobility_test_support.hpp"
#include "rfsitl/common/geodesy.hpp"
#include "rfsitl/position/mobility/orbit_model.hpp"
#include "rfsitl/position/mobility/static_model.hpp"

namespace rfsitl::position::mobility {
namespace {

using testing::near;
using testing::velocity_is_derivative;
constexpr double kPi = std::numbers::pi;
const GeodeticPosition kOrigin{43.0008, -78.789, 180.0};

TEST(MobilityStatic, StaysPutWithZeroVelocityInEitherFrame) {
  StaticModel local(StaticSettings{LocalPosition{12.5, -3, 40}}, kOrigin);
  for (const double t : {-5.0, 0.0, 1e-3, 3600.0}) {
    EXPECT_TRUE(near(local.state_at(t).position, {12.5, -3, 40}));
    EXPECT_TRUE(near(local.state_at(t).velocity, {0, 0, 0}, 0.0));
  }
  // A WGS84 point lands where the channel's own geodesy puts it.
  const GeodeticPosition g{43.0018, -78.788, 230.0};
  StaticModel geo(StaticSettings{g}, kOrigin);
  const LocalPosition want = ecef_to_local(geodetic_to_ecef(g), kOrigin);
  EXPECT_TRUE(near(geo.state_at(7).position, want, 1e-9));
  EXPECT_NEAR(want.y_m, 111.0, 1.0);  // a thousandth of a degree north
}

TEST(MobilityStatic, RefusesAPositionOutOfLimits) {
  EXPECT_THROW(StaticModel(StaticSettings{GeodeticPosition{91, 0, 0}}, kOrigin),
               std::invalid_argument);
  try {
    StaticModel(StaticSettings{LocalPosition{0, 0, 2e5}}, kOrigin);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "static.position: z 200000 out of range [-1000, 100000]");
  }
}

OrbitSettings orbit(double speed, double phase) {
  OrbitSettings s;
  s.centre_x_m = 100;
  s.centre_y_m = -50;
  s.radius_m = 200;
  s.speed_mps = speed;
  s.altitude_m = 120;
  s.phase_rad = phase;
  return s;
}

TEST(MobilityOrbit, CounterClockwiseFromTheEastPointAtPositiveSpeed) {
  OrbitModel m(orbit(20, 0));  // a quarter turn (100 pi m) takes 5 pi s
  EXPECT_TRUE(near(m.state_at(0).position, {300, -50, 120}));
  EXPECT_TRUE(near(m.state_at(0).velocity, {0, 20, 0}));  // heading north
  EXPECT_TRUE(near(m.state_at(5 * kPi).position, {100, 150, 120}));
  EXPECT_TRUE(near(m.state_at(5 * kPi).velocity, {-20, 0, 0}));
  EXPECT_TRUE(near(m.state_at(10 * kPi).position, {-100, -50, 120}));
  EXPECT_TRUE(near(m.state_at(20 * kPi).position, {300, -50, 120}));    // one lap
  EXPECT_TRUE(near(m.state_at(2000 * kPi).position, {300, -50, 120}));  // a hundred laps
}

TEST(MobilityOrbit, NegativeSpeedFliesClockwiseAndPhaseSetsTheStart) {
  OrbitModel m(orbit(-20, kPi / 2));  // starts due north of the centre
  EXPECT_TRUE(near(m.state_at(0).position, {100, 150, 120}));
  EXPECT_TRUE(near(m.state_at(0).velocity, {20, 0, 0}));  // clockwise: heading east
  EXPECT_TRUE(near(m.state_at(5 * kPi).position, {300, -50, 120}));
  EXPECT_TRUE(near(m.state_at(-5 * kPi).position, {-100, -50, 120}));  // and before t = 0
}

TEST(MobilityOrbit, MatchesTheFormulaAndItsDerivativeEverywhere) {
  const OrbitSettings s = orbit(-13.7, 2.1);
  OrbitModel m(s);
  for (double t = 0; t < 300; t += 7.3) {
    const double a = s.phase_rad + s.speed_mps / s.radius_m * t;
    const MotionState st = m.state_at(t);
    EXPECT_TRUE(near(st.position, {s.centre_x_m + s.radius_m * std::cos(a),
                                   s.centre_y_m + s.radius_m * std::sin(a), s.altitude_m}));
    EXPECT_NEAR(std::hypot(st.velocity.vx_mps, st.velocity.vy_mps), 13.7, 1e-9);
    EXPECT_TRUE(velocity_is_derivative(m, t));
  }
}

TEST(MobilityOrbit, ZeroSpeedHovers) {
  OrbitModel m(orbit(0, kPi));
  EXPECT_TRUE(near(m.state_at(1000).position, {-100, -50, 120}));
  EXPECT_TRUE(near(m.state_at(1000).velocity, {0, 0, 0}, 0.0));
}

TEST(MobilityOrbit, ValidationNamesTheField) {
  auto message = [](OrbitSettings s) {
    try {
      s.validate();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  OrbitSettings s = orbit(10, 0);
  EXPECT_EQ(message(s), "accepted");
  s.radius_m = 0;
  EXPECT_EQ(message(s), "orbit.radius_m must be > 0 and <= 1e8 (got 0)");
  s = orbit(std::nan(""), 0);
  EXPECT_EQ(message(s), "orbit.speed_mps must be finite (got nan)");
  s = orbit(10, 0);
  s.altitude_m = -5000;
  EXPECT_EQ(message(s), "orbit.centre: z -5000 out of range [-1000, 100000]");
  EXPECT_THROW(OrbitModel{orbit(10, INFINITY)}, std::invalid_argument);
}

}  // namespace
}  // namespace rfsitl::position::mobility
