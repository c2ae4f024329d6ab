#include "rfsitl/channel/geodesy.hpp"

#include <cmath>
#include <numbers>
#include <type_traits>
#include <variant>

namespace rfsitl::channel {
namespace {

// WGS84 defining constants (NIMA TR8350.2). The first eccentricity squared is
// derived from the flattening rather than typed in, so it carries full double
// precision.
constexpr double kSemiMajorAxisM = 6378137.0;
constexpr double kFlattening = 1.0 / 298.257223563;
constexpr double kEccentricitySq = kFlattening * (2.0 - kFlattening);

constexpr double kDegToRad = std::numbers::pi / 180.0;

}  // namespace

Ecef geodetic_to_ecef(const GeodeticPosition& p) {
  const double lat = p.lat_deg * kDegToRad;
  const double lon = p.lon_deg * kDegToRad;
  const double sin_lat = std::sin(lat);
  const double cos_lat = std::cos(lat);
  // Prime-vertical radius of curvature at this latitude.
  const double n = kSemiMajorAxisM / std::sqrt(1.0 - kEccentricitySq * sin_lat * sin_lat);
  const double r = (n + p.alt_m) * cos_lat;
  return Ecef{r * std::cos(lon), r * std::sin(lon),
              (n * (1.0 - kEccentricitySq) + p.alt_m) * sin_lat};
}

Ecef local_to_ecef(const LocalPosition& p, const GeodeticPosition& origin) {
  const Ecef o = geodetic_to_ecef(origin);
  const double lat = origin.lat_deg * kDegToRad;
  const double lon = origin.lon_deg * kDegToRad;
  const double sl = std::sin(lat);
  const double cl = std::cos(lat);
  const double so = std::sin(lon);
  const double co = std::cos(lon);
  // Columns of the rotation are the east, north and up unit vectors of the
  // origin's tangent plane expressed in ECEF.
  const double east = p.x_m;
  const double north = p.y_m;
  const double up = p.z_m;
  return Ecef{o.x - so * east - sl * co * north + cl * co * up,  //
              o.y + co * east - sl * so * north + cl * so * up,  //
              o.z + cl * north + sl * up};
}

Ecef to_ecef(const Position& p, const GeodeticPosition& origin) {
  return std::visit(
      [&origin](const auto& q) -> Ecef {
        if constexpr (std::is_same_v<std::decay_t<decltype(q)>, GeodeticPosition>) {
          return geodetic_to_ecef(q);
        } else {
          return local_to_ecef(q, origin);
        }
      },
      p);
}

double distance_m(const Ecef& a, const Ecef& b) {
  // hypot avoids overflow/underflow of the squares; cost is irrelevant here
  // because distances are only recomputed when a position changes.
  return std::hypot(a.x - b.x, a.y - b.y, a.z - b.z);
}

}  // namespace rfsitl::channel
