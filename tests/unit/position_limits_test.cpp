// The one set of position limits, and the location port applying exactly them.
#include "rfsitl/common/position_limits.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "rfsitl/position/location_port/location_line.hpp"

namespace rfsitl {
namespace {

TEST(PositionLimits, ErrorsNameTheFieldTheValueAndTheLimit) {
  EXPECT_EQ(coordinate_error("z", 500000, kAltitudeLimit), "z 500000 out of range [-1000, 100000]");
  EXPECT_EQ(coordinate_error("z", -50000, kAltitudeLimit), "z -50000 out of range [-1000, 100000]");
  EXPECT_EQ(coordinate_error("latitude", 91.5, kLatitudeLimit),
            "latitude 91.5 out of range [-90, 90]");
  EXPECT_EQ(coordinate_error("x", std::nan(""), kHorizontalLimit),
            "x is not a finite number (nan)");
  EXPECT_EQ(coordinate_error("y", -std::numeric_limits<double>::infinity(), kHorizontalLimit),
            "y is not a finite number (-inf)");
  EXPECT_EQ(coordinate_error("z", 100000, kAltitudeLimit), "");  // limits are inclusive
  EXPECT_EQ(coordinate_error("z", -1000, kAltitudeLimit), "");

  EXPECT_EQ(position_error(GeodeticPosition{0, 180.5, 0}),
            "longitude 180.5 out of range [-180, 180]");
  EXPECT_EQ(position_error(GeodeticPosition{10, 10, 100001}),
            "altitude 100001 out of range [-1000, 100000]");
  EXPECT_EQ(position_error(LocalPosition{1e7, -1e7, 0}), "");  // x, y: +-10 000 km, inclusive
  EXPECT_EQ(position_error(LocalPosition{1.7e308, 0, 0}),
            "x 1.7e+308 out of range [-10000000, 10000000]");
  EXPECT_EQ(position_error(LocalPosition{0, -1e7 - 0.5, 0}),
            "y -10000000.5 out of range [-10000000, 10000000]");
  EXPECT_EQ(position_error(LocalPosition{0, 0, 100000.5}),
            "z 100000.5 out of range [-1000, 100000]");
  EXPECT_EQ(position_error(GeodeticPosition{-90, -180, -1000}), "");
}

TEST(PositionLimits, TheLocationPortRefusesExactlyWhatTheLimitsRefuse) {
  const double values[] = {-1.7e308, -1e7 - 0.5, -1e7,   -1e6, -100001,   -1000.5, -1000, -181,
                           -180,     -90.5,      -90,    0,    90,        90.5,    180,   180.5,
                           100000,   100000.5,   500000, 1e7,  1e7 + 0.5, 1.7e308};
  for (const double a : values) {
    for (const double b : values) {
      const std::string plain = format_coordinate(a) + " " + format_coordinate(b) + " 10";
      const auto r = position::parse_location_line(plain);
      EXPECT_EQ(r.error, position_error(GeodeticPosition{a, b, 10})) << plain;
      const std::string local =
          R"({"x": 1, "y": )" + format_coordinate(a) + R"(, "z": )" + format_coordinate(b) + "}";
      const auto l = position::parse_location_line(local);
      EXPECT_EQ(l.error, position_error(LocalPosition{1, a, b})) << local;
    }
  }
}

}  // namespace
}  // namespace rfsitl
