#include <gtest/gtest.h>

#include <vector>

#include "rfsitl/common/geodesy.hpp"

namespace rfsitl::channel {
namespace {

TEST(GeodesyInverse, GeodeticRoundTripIsExactToMicrodegreesAndMillimetres) {
  const std::vector<GeodeticPosition> points = {{43.0008, -78.789, 120.0}, {0.0, 0.0, 0.0},
                                                {-33.9, 151.2, 5.0},       {89.9999, 10.0, 1000.0},
                                                {-89.5, -170.0, 0.0},      {60.0, 179.99, 30000.0}};
  for (const auto& p : points) {
    const GeodeticPosition q = ecef_to_geodetic(geodetic_to_ecef(p));
    EXPECT_NEAR(q.lat_deg, p.lat_deg, 1e-9) << p.lat_deg;
    EXPECT_NEAR(q.lon_deg, p.lon_deg, 1e-9) << p.lon_deg;
    EXPECT_NEAR(q.alt_m, p.alt_m, 1e-3) << p.lat_deg;
  }
}

TEST(GeodesyInverse, LocalRoundTripAroundTheOriginIsExactToMicrometres) {
  const GeodeticPosition origin{43.0008, -78.789, 0.0};
  for (const LocalPosition l : {LocalPosition{0, 0, 0}, LocalPosition{120.5, -40.25, 12.0},
                                LocalPosition{-3000, 2500, 400}}) {
    const LocalPosition back = ecef_to_local(local_to_ecef(l, origin), origin);
    EXPECT_NEAR(back.x_m, l.x_m, 1e-6);
    EXPECT_NEAR(back.y_m, l.y_m, 1e-6);
    EXPECT_NEAR(back.z_m, l.z_m, 1e-6);
  }
}

TEST(GeodesyInverse, PointDueNorthOfOriginHasPositiveNorthAndNoEast) {
  const GeodeticPosition origin{45.0, 7.0, 0.0};
  const LocalPosition l = ecef_to_local(geodetic_to_ecef({45.001, 7.0, 0.0}), origin);
  EXPECT_NEAR(l.x_m, 0.0, 1e-6);
  EXPECT_NEAR(l.y_m, 111.1, 0.2);  // a thousandth of a degree of latitude at 45 N
  EXPECT_LT(l.z_m, 0.0);           // the ellipsoid curves away below the tangent plane
}

}  // namespace
}  // namespace rfsitl::channel
