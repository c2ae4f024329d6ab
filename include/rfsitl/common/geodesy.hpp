#pragma once
/// Exact WGS84 conversions. Distances between nodes are straight lines in ECEF,
/// never a flat-earth approximation.
#include "rfsitl/common/position.hpp"

namespace rfsitl {

/// WGS84 geodetic (lat, lon, ellipsoidal height) to ECEF.
Ecef geodetic_to_ecef(const GeodeticPosition& p);

/// Local ENU metres around `origin` to ECEF.
Ecef local_to_ecef(const LocalPosition& p, const GeodeticPosition& origin);

/// Resolves either kind of position to ECEF; local positions use `origin`.
Ecef to_ecef(const Position& p, const GeodeticPosition& origin);

/// ECEF back to local ENU metres around `origin` (the inverse of local_to_ecef).
LocalPosition ecef_to_local(const Ecef& p, const GeodeticPosition& origin);

/// ECEF back to WGS84 geodetic (Bowring's method with two refinements: well
/// under a millimetre anywhere near the Earth's surface).
GeodeticPosition ecef_to_geodetic(const Ecef& p);

/// Euclidean distance in metres.
double distance_m(const Ecef& a, const Ecef& b);

}  // namespace rfsitl
