#include "rfsitl/common/geodesy.hpp"

#include <cmath>
#include <numbers>
#include <type_traits>
#include <variant>

namespace rfsitl {
namespace {

// WGS84 defining constants (NIMA TR8350.2). The first eccentricity squared is
// derived from the flattening rather than typed in, so it carries full double
// precision.
constexpr double kSemiMajorAxisM = 6378137.0;
constexpr double kFlattening = 1.0 / 298.257223563;
constexpr double kEccentricitySq = kFlattening * (2.0 - kFlattening);

constexpr double kDegToRad = std::numbers::pi / 180.0;

/// The east, north and up unit vectors of the tangent plane at `origin`, in
/// ECEF: the columns of local_to_ecef's rotation (and rows of its inverse).
struct EnuBasis {
  double sl, cl, so, co;  // sin/cos of latitude and longitude
  explicit EnuBasis(const GeodeticPosition& origin)
      : sl(std::sin(origin.lat_deg * kDegToRad)),
        cl(std::cos(origin.lat_deg * kDegToRad)),
        so(std::sin(origin.lon_deg * kDegToRad)),
        co(std::cos(origin.lon_deg * kDegToRad)) {}
};

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
  const EnuBasis b(origin);
  const double east = p.x_m;
  const double north = p.y_m;
  const double up = p.z_m;
  return Ecef{o.x - b.so * east - b.sl * b.co * north + b.cl * b.co * up,  //
              o.y + b.co * east - b.sl * b.so * north + b.cl * b.so * up,  //
              o.z + b.cl * north + b.sl * up};
}

LocalPosition ecef_to_local(const Ecef& p, const GeodeticPosition& origin) {
  const Ecef o = geodetic_to_ecef(origin);
  const EnuBasis b(origin);
  const double dx = p.x - o.x;
  const double dy = p.y - o.y;
  const double dz = p.z - o.z;
  // The transpose of local_to_ecef's rotation.
  return LocalPosition{-b.so * dx + b.co * dy,  //
                       -b.sl * b.co * dx - b.sl * b.so * dy + b.cl * dz,
                       b.cl * b.co * dx + b.cl * b.so * dy + b.sl * dz};
}

GeodeticPosition ecef_to_geodetic(const Ecef& p) {
  const double b = kSemiMajorAxisM * (1.0 - kFlattening);
  const double ep2 = kEccentricitySq / (1.0 - kEccentricitySq);
  const double r = std::hypot(p.x, p.y);
  const double lon = std::atan2(p.y, p.x);
  // Bowring's parametric-latitude start, then fixed-point refinements.
  double beta = std::atan2(p.z * kSemiMajorAxisM, r * b);
  double lat = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double sb = std::sin(beta);
    const double cb = std::cos(beta);
    lat = std::atan2(p.z + ep2 * b * sb * sb * sb,
                     r - kEccentricitySq * kSemiMajorAxisM * cb * cb * cb);
    beta = std::atan2((1.0 - kFlattening) * std::sin(lat), std::cos(lat));
  }
  const double sl = std::sin(lat);
  const double n = kSemiMajorAxisM / std::sqrt(1.0 - kEccentricitySq * sl * sl);
  const double alt = std::abs(std::cos(lat)) > 1e-9 ? r / std::cos(lat) - n : std::abs(p.z) - b;
  return GeodeticPosition{lat / kDegToRad, lon / kDegToRad, alt};
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

}  // namespace rfsitl
