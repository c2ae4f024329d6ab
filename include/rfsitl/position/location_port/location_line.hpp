#pragma once
/// Parses one line of a location feed. Accepted forms (one position per line):
///   "lat lon alt"  decimal degrees and metres, separated by spaces and/or commas;
///   {"lat":..,"lon":..,"alt":..}   JSON object (alt optional, default 0);
///   {"x":..,"y":..,"z":..}         JSON object, local ENU metres (z optional, default 0);
///   $GPGGA / $GNGGA NMEA 0183 sentence; the checksum is verified, and altitude is
///   MSL altitude plus geoid separation (ellipsoidal height).
#include <optional>
#include <string>
#include <string_view>

#include "rfsitl/common/position.hpp"

namespace rfsitl::position {

struct LocationParseResult {
  /// Set when the line held a valid position.
  std::optional<Position> position;
  /// Set when the line was rejected: the reason, naming the field at fault.
  std::string error;
  /// True for lines that carry nothing (empty or whitespace): neither position nor error.
  bool blank = false;
};

/// Precondition: `line` has no trailing newline (a trailing '\r' is tolerated).
/// Range checks (rfsitl/common/position_limits.hpp): |lat| <= 90, |lon| <= 180,
/// -1000 <= alt (and local z) <= 100000 m; all numbers finite.
/// A GGA sentence with fix quality 0 (no fix) is rejected.
LocationParseResult parse_location_line(std::string_view line);

}  // namespace rfsitl::position
