#pragma once
/// ns-2 movement files (as CMU setdest and BonnMotion's NSFile export write them):
///   $node_(i) set X_ 10.0                          initial x (also Y_, Z_)
///   $ns_ at 2.0 "$node_(i) setdest 50.0 20.0 5.0"   at t = 2 s head for (50, 20) at 5 m/s
///   $ns_ at 9.0 "$node_(i) set X_ 0.0"              at t = 9 s jump to x = 0 (also Y_, Z_)
/// Coordinates are local metres (X_ east, Y_ north, Z_ up; unset ones are 0).
///
/// Replayed exactly as ns-2 moves a node: at a setdest's time the node leaves
/// its position at that instant in a straight line towards the destination at
/// the given speed and stops there; a later setdest (or a timed set) interrupts
/// the leg wherever the node is. setdest moves x and y only (ns-2 is planar; z
/// keeps its value). Speed 0, or a destination where the node already is, stops
/// the node where it is. A timed `set` moves the node at once and stops it.
/// Initial `set` lines may come anywhere in the file; a node's events happen in
/// time order (file order among equal times), whatever their order in the file.
///
/// Skipped silently: blank lines, '#' comments, and `$god_` statements (the
/// hop counts setdest adds), plain or timed. Anything else that is not one of
/// the three forms above, a time that is not a number in [0, kMaxTraceTimeS], a node
/// outside 0..65535, a coordinate out of limits (as in csv_trace.hpp), a speed
/// negative, not finite or too small for the leg ever to end, is skipped and
/// reported.
#include <string>
#include <string_view>

#include "rfsitl/position/mobility/trace_parse_result.hpp"

namespace rfsitl::position::mobility {

/// Parses `text`; `source` names it in messages. Never throws for any content.
/// Each node's track starts with a knot at t = 0 at its initial position.
TraceParseResult parse_ns2_trace(std::string_view text, std::string source);

/// Reads and parses the file at `path`. Throws std::runtime_error
/// ("path: cannot read: reason") when the file cannot be read.
TraceParseResult read_ns2_trace(const std::string& path);

}  // namespace rfsitl::position::mobility
