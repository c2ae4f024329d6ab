#pragma once
/// Recorded positions as CSV, one sample per line:
///   t, node, x, y, z        (virtual seconds, node number, local ENU metres), or
///   t, node, lat, lon, alt  (WGS84 degrees and metres above the ellipsoid).
///
/// Which form: a header names it. The file's first line that is neither blank
/// nor a comment ('#') is a header when its first field is `t`, and must then
/// read exactly `t,node,x,y,z` or `t,node,lat,lon,alt` (spaces around fields
/// and case ignored); any other header is reported and nothing more of the file
/// is read, since its columns cannot be known. Without a header the caller's
/// `headerless` form applies: the values alone cannot tell degrees from metres.
///
/// Rules per row: five comma-separated fields; t finite, in [0, kMaxTraceTimeS]; node an
/// integer in 0..65535; coordinates within rfsitl/common/position_limits.hpp
/// (and local ones within kMaxLocalCoordinateM); a node's samples in
/// non-decreasing time (two at the same time are a jump). A row that breaks one
/// is skipped and reported. Each node's samples make a PiecewiseLinearTrack:
/// linear between samples, the first before its time, the last after.
#include <string>
#include <string_view>

#include "rfsitl/common/position.hpp"
#include "rfsitl/position/mobility/trace_parse_result.hpp"

namespace rfsitl::position::mobility {

enum class CsvCoordinates { kLocal, kGeodetic };

struct CsvTraceOptions {
  /// The scenario origin: WGS84 rows are converted to local ENU around it once,
  /// as they are read.
  GeodeticPosition origin;
  /// The form of a file without a header.
  CsvCoordinates headerless = CsvCoordinates::kLocal;
};

/// Parses `text`; `source` names it in messages. Never throws for any content.
TraceParseResult parse_csv_trace(std::string_view text, std::string source,
                                 const CsvTraceOptions& options);

/// Reads and parses the file at `path`. Throws std::runtime_error
/// ("path: cannot read: reason") when the file cannot be read.
TraceParseResult read_csv_trace(const std::string& path, const CsvTraceOptions& options);

}  // namespace rfsitl::position::mobility
