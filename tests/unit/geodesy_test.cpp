#include "rfsitl/common/geodesy.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace rfsitl::channel {
namespace {

// WGS84, restated here so the tests do not share a typo with the implementation.
constexpr double kA = 6378137.0;
constexpr double kF = 1.0 / 298.257223563;
constexpr double kB = kA * (1.0 - kF);  // 6356752.314245179 m
constexpr double kE2 = kF * (2.0 - kF);

void expect_ecef_near(const Ecef& got, const Ecef& want, double tol_m) {
  EXPECT_NEAR(got.x, want.x, tol_m);
  EXPECT_NEAR(got.y, want.y, tol_m);
  EXPECT_NEAR(got.z, want.z, tol_m);
}

TEST(Geodesy, EquatorPrimeMeridianMapsToSemiMajorAxisOnX) {
  expect_ecef_near(geodetic_to_ecef({0.0, 0.0, 0.0}), {kA, 0.0, 0.0}, 1e-9);
}

TEST(Geodesy, NorthPoleMapsToSemiMinorAxisOnZ) {
  // cos(pi/2) is 6e-17 in double, so x is a few 1e-10 m rather than exactly 0.
  expect_ecef_near(geodetic_to_ecef({90.0, 0.0, 0.0}), {0.0, 0.0, kB}, 1e-6);
  EXPECT_NEAR(geodetic_to_ecef({90.0, 0.0, 0.0}).z, 6356752.314245, 1e-6);
}

TEST(Geodesy, EquatorAt90EastWithAltitudeLiesOnYAxis) {
  expect_ecef_near(geodetic_to_ecef({0.0, 90.0, 1000.0}), {0.0, kA + 1000.0, 0.0}, 1e-6);
}

TEST(Geodesy, AltitudeIsMeasuredAlongTheEllipsoidNormal) {
  const Ecef ground = geodetic_to_ecef({45.0, 10.0, 0.0});
  const Ecef above = geodetic_to_ecef({45.0, 10.0, 100.0});
  EXPECT_NEAR(distance_m(ground, above), 100.0, 1e-6);
}

TEST(Geodesy, OneKilometreMeridianArcNorthAt45NIsOneKilometreStraightLine) {
  // Meridional radius of curvature at 45 N:
  //   M = a (1 - e^2) / (1 - e^2 sin^2(45))^1.5 = 6367381.8156 m,
  // so a 1000 m arc north is dphi = 1000 / M rad = 0.0089983263 deg.
  // Error budget against 1000 m: chord vs arc = arc * dphi^2 / 24 ~ 1e-6 m;
  // M varies by ~1.6e-6 relative over the arc, i.e. < 1 mm. A spherical
  // (R = 6371 km) or flat-earth shortcut would be off by about 0.6 m.
  const double phi = 45.0 * std::numbers::pi / 180.0;
  const double s = std::sin(phi);
  const double m = kA * (1.0 - kE2) / std::pow(1.0 - kE2 * s * s, 1.5);
  ASSERT_NEAR(m, 6367381.8156, 1e-3);
  const double dphi_deg = (1000.0 / m) * 180.0 / std::numbers::pi;

  const Ecef south = geodetic_to_ecef({45.0, 0.0, 0.0});
  const Ecef north = geodetic_to_ecef({45.0 + dphi_deg, 0.0, 0.0});
  EXPECT_NEAR(distance_m(south, north), 1000.0, 0.01);
}

TEST(Geodesy, DistanceIsEuclideanAndSymmetric) {
  const Ecef a{1.0, 2.0, 3.0};
  const Ecef b{4.0, 6.0, 15.0};  // deltas 3, 4, 12 -> 13
  EXPECT_DOUBLE_EQ(distance_m(a, b), 13.0);
  EXPECT_DOUBLE_EQ(distance_m(b, a), 13.0);
  EXPECT_DOUBLE_EQ(distance_m(a, a), 0.0);
}

TEST(Geodesy, LocalOriginIsTheOriginItself) {
  const GeodeticPosition origin{43.0, -78.8, 200.0};
  expect_ecef_near(local_to_ecef({0.0, 0.0, 0.0}, origin), geodetic_to_ecef(origin), 1e-9);
}

TEST(Geodesy, LocalHundredMetresEastIsHundredMetresFromOrigin) {
  const GeodeticPosition origin{43.0, -78.8, 200.0};
  const Ecef o = geodetic_to_ecef(origin);
  EXPECT_NEAR(distance_m(local_to_ecef({100.0, 0.0, 0.0}, origin), o), 100.0, 1e-6);
  EXPECT_NEAR(distance_m(local_to_ecef({0.0, 100.0, 0.0}, origin), o), 100.0, 1e-6);
  EXPECT_NEAR(distance_m(local_to_ecef({30.0, 40.0, 0.0}, origin), o), 50.0, 1e-6);
}

TEST(Geodesy, LocalUpIsGeodeticAltitude) {
  // Up in ENU is the ellipsoid normal at the origin, so 50 m up is the same
  // point as the origin with 50 m more ellipsoidal height.
  const GeodeticPosition origin{43.0, -78.8, 200.0};
  const Ecef up = local_to_ecef({0.0, 0.0, 50.0}, origin);
  EXPECT_NEAR(distance_m(up, geodetic_to_ecef(origin)), 50.0, 1e-6);
  expect_ecef_near(up, geodetic_to_ecef({43.0, -78.8, 250.0}), 1e-6);
}

TEST(Geodesy, LocalAxesAtEquatorPrimeMeridianAreEcefYZX) {
  // At (0, 0) east = +y, north = +z, up = +x: checks the rotation's signs.
  const GeodeticPosition origin{0.0, 0.0, 0.0};
  expect_ecef_near(local_to_ecef({100.0, 0.0, 0.0}, origin), {kA, 100.0, 0.0}, 1e-6);
  expect_ecef_near(local_to_ecef({0.0, 100.0, 0.0}, origin), {kA, 0.0, 100.0}, 1e-6);
  expect_ecef_near(local_to_ecef({0.0, 0.0, 100.0}, origin), {kA + 100.0, 0.0, 0.0}, 1e-6);
}

TEST(Geodesy, ToEcefDispatchesOnPositionKind) {
  const GeodeticPosition origin{43.0, -78.8, 200.0};
  const Position geo = GeodeticPosition{10.0, 20.0, 30.0};
  const Position local = LocalPosition{5.0, 6.0, 7.0};
  expect_ecef_near(to_ecef(geo, origin), geodetic_to_ecef({10.0, 20.0, 30.0}), 1e-9);
  expect_ecef_near(to_ecef(local, origin), local_to_ecef({5.0, 6.0, 7.0}, origin), 1e-9);
}

}  // namespace
}  // namespace rfsitl::channel
