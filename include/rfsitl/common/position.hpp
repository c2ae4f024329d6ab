#pragma once
/// Positions as a location feed reports them.
#include <variant>

namespace rfsitl {

/// WGS84 geodetic position: latitude and longitude in decimal degrees,
/// altitude in metres above the ellipsoid.
struct GeodeticPosition {
  double lat_deg = 0.0;
  double lon_deg = 0.0;
  double alt_m = 0.0;
};

/// Local east/north/up position in metres relative to the scenario origin.
struct LocalPosition {
  double x_m = 0.0;  ///< east
  double y_m = 0.0;  ///< north
  double z_m = 0.0;  ///< up
};

using Position = std::variant<GeodeticPosition, LocalPosition>;

/// Earth-centred, Earth-fixed cartesian coordinates in metres.
struct Ecef {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
};

}  // namespace rfsitl
