#pragma once
/// Positions given either way (WGS84 or local metres) brought into the one frame
/// the mobility models interpolate in: local east/north/up around the scenario
/// origin.
#include <string>

#include "rfsitl/common/position.hpp"

namespace rfsitl::position::mobility {

/// The largest |x|, |y| or |z| in metres any mobility model accepts in the local
/// frame (every WGS84 position is within 1.3e7 of any origin). A bound keeps
/// every difference, speed and interpolation finite.
inline constexpr double kMaxLocalCoordinateM = 1e8;

/// "" when `p` has finite coordinates within kMaxLocalCoordinateM, else why not,
/// naming the axis ("x 2e+08 is beyond +-1e8 m of the origin").
std::string local_coordinate_error(const LocalPosition& p);

/// `p` in local ENU metres around `origin`: a LocalPosition as it is, a
/// GeodeticPosition converted exactly (through ECEF, rfsitl/common/geodesy.hpp).
/// Models call this once, at construction, never per evaluation, so a leg
/// between two geodetic points is a straight chord in the local frame, not a
/// path at constant altitude: between two points at the same altitude L apart
/// it passes L^2 / (8 R) lower in the middle (R ~ 6371 km: 2 cm at 1 km, 2 m
/// at 10 km).
LocalPosition to_local(const Position& p, const GeodeticPosition& origin);

}  // namespace rfsitl::position::mobility
