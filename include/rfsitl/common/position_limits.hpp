#pragma once
/// The positions every input accepts: the location ports (io/location_parser),
/// the dashboard's move requests, scenario files (src/scenario/scenario_validation.cpp
/// checks against these very constants), mobility traces and MAVLink vehicles.
/// One place, so a position one input refuses is refused by all of them.
#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <variant>

#include "rfsitl/common/position.hpp"

namespace rfsitl {

/// A closed interval; NaN and infinities are never inside.
struct CoordinateLimit {
  double lo;
  double hi;
  constexpr bool contains(double v) const { return v >= lo && v <= hi; }
};

inline constexpr CoordinateLimit kLatitudeLimit{-90.0, 90.0};     ///< degrees
inline constexpr CoordinateLimit kLongitudeLimit{-180.0, 180.0};  ///< degrees
/// Metres above the ellipsoid; also bounds local z (height above the origin).
inline constexpr CoordinateLimit kAltitudeLimit{-1000.0, 100000.0};
/// Local x and y (east, north), metres from the origin: 10 000 km either way.
/// Local positions lie on the origin's tangent plane (ENU), which leaves the
/// Earth's surface as d^2 / 2R (R ~ 6371 km): 8 km up at 320 km, 7800 km up at
/// 10 000 km, where no place a radio link is meant for lies any more (a
/// far-away place is given as lat/lon instead). The bound also keeps distances,
/// their squares in the path loss, and ECEF sums far from overflow (finite
/// alone let 1.7e308 through).
inline constexpr CoordinateLimit kHorizontalLimit{-1e7, 1e7};

/// Shortest text that reads back as the same double, so messages quote a value
/// exactly as it was understood ("91.5", not "91.500000"); plain notation for the
/// magnitudes a position can have, so a limit reads "100000", not "1e+05".
inline std::string format_coordinate(double v) {
  char buf[64];
  const double mag = std::fabs(v);
  const bool plain = v == 0.0 || (mag >= 1e-4 && mag < 1e15);
  const auto res = plain ? std::to_chars(buf, buf + sizeof(buf), v, std::chars_format::fixed)
                         : std::to_chars(buf, buf + sizeof(buf), v);
  return std::string(buf, res.ptr);
}

/// "" when `v` is within `limit`, else why not, naming `field`, the value and
/// the limit: "latitude 91.5 out of range [-90, 90]", "x is not a finite number (nan)".
inline std::string coordinate_error(std::string_view field, double v, CoordinateLimit limit) {
  if (!std::isfinite(v)) {
    return std::string(field) + " is not a finite number (" + format_coordinate(v) + ")";
  }
  if (limit.contains(v)) return "";
  return std::string(field) + " " + format_coordinate(v) + " out of range [" +
         format_coordinate(limit.lo) + ", " + format_coordinate(limit.hi) + "]";
}

/// "" when every coordinate of `p` is within its limit, else the first
/// coordinate_error (fields "latitude", "longitude", "altitude" or "x", "y", "z").
inline std::string position_error(const Position& p) {
  std::string e;
  if (const auto* g = std::get_if<GeodeticPosition>(&p)) {
    if (e = coordinate_error("latitude", g->lat_deg, kLatitudeLimit); !e.empty()) return e;
    if (e = coordinate_error("longitude", g->lon_deg, kLongitudeLimit); !e.empty()) return e;
    return coordinate_error("altitude", g->alt_m, kAltitudeLimit);
  }
  const auto& l = std::get<LocalPosition>(p);
  if (e = coordinate_error("x", l.x_m, kHorizontalLimit); !e.empty()) return e;
  if (e = coordinate_error("y", l.y_m, kHorizontalLimit); !e.empty()) return e;
  return coordinate_error("z", l.z_m, kAltitudeLimit);
}

}  // namespace rfsitl
