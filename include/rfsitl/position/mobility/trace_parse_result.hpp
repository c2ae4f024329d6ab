#pragma once
/// What reading a mobility trace file gives: a track per node, and every line
/// it could not use with the reason. A bad line never stops the run: it is
/// skipped and counted, and the node's previous good sample stays in force.
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "rfsitl/position/mobility/piecewise_linear_track.hpp"

namespace rfsitl::position::mobility {

/// One skipped line: its number (1-based) and why ("node 70000 is not an
/// integer in 0..65535").
struct TraceLineError {
  std::size_t line = 0;
  std::string reason;
};

struct TraceParseResult {
  /// The most errors kept with their reasons; bad_lines counts all of them.
  static constexpr std::size_t kMaxReportedErrors = 100;
  /// The largest node number a trace may name.
  static constexpr std::uint32_t kMaxNode = 65535;
  /// The latest time a trace may name, s (~31700 years): with it every derived
  /// time (an ns-2 leg's arrival) stays finite.
  static constexpr double kMaxTraceTimeS = 1e12;

  std::string source;  ///< the file name as given, for messages
  /// One track per node number of the file (as written: ns-2 counts from 0),
  /// each with at least one knot.
  std::map<std::uint32_t, PiecewiseLinearTrack> tracks;
  std::size_t bad_lines = 0;           ///< every line skipped
  std::vector<TraceLineError> errors;  ///< the first kMaxReportedErrors, in line order

  /// "source:line: reason", as logged.
  std::string message(const TraceLineError& e) const;
};

}  // namespace rfsitl::position::mobility
