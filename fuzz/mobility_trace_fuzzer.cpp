/// Mobility traces: parse_csv_trace and parse_ns2_trace on arbitrary text.
/// Input: [mode byte][text]; bit 0 of the mode picks the CSV headerless form
/// (local / WGS84). Both parsers read every input.
///
/// Checks, for both parsers:
///  - nothing escapes (an exception is a crash);
///  - each skipped line is counted once: error line numbers strictly increase,
///    lie within the text, carry a reason; errors kept = min(bad lines, 100);
///  - every track has knots with finite, non-decreasing times >= 0 (CSV: <= 1e12) and
///    finite positions within kMaxLocalCoordinateM;
///  - replay is exact and tame: at each knot's time (the last of equal times)
///    the state is that knot's position exactly; between knots it is
///    finite and within the two knots' bounding box (1 um slack); before the
///    first knot and after the last it holds them with zero velocity;
///  - parsing is deterministic.
/// CSV: accepted samples + bad lines = lines with content, less one for a
/// header (an unknown header is the one error, with no tracks).
/// ns-2: every track starts at t = 0 and no segment moves in z (setdest is
/// planar; a Z_ change is a jump, not a segment).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "fuzz_check.hpp"
#include "rfsitl/position/mobility/csv_trace.hpp"
#include "rfsitl/position/mobility/local_frame.hpp"
#include "rfsitl/position/mobility/ns2_trace.hpp"

using namespace rfsitl;
using namespace rfsitl::position::mobility;

namespace {

struct LineCounts {
  std::size_t lines = 0;    // as the parsers number them
  std::size_t content = 0;  // neither blank (spaces, tabs) nor a '#' comment
};

LineCounts count_lines(std::string_view text) {
  LineCounts c;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    ++c.lines;
    const std::size_t first = line.find_first_not_of(" \t");
    if (first != std::string_view::npos && line[first] != '#') ++c.content;
    start = end + 1;
  }
  return c;
}

bool same_bits(const LocalPosition& a, const LocalPosition& b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

/// Equal values (-0 is 0: a knot at x = -0 replays at 0).
bool equal(const LocalPosition& a, const LocalPosition& b) {
  return a.x_m == b.x_m && a.y_m == b.y_m && a.z_m == b.z_m;
}

bool finite(const MotionState& s) {
  return std::isfinite(s.position.x_m) && std::isfinite(s.position.y_m) &&
         std::isfinite(s.position.z_m) && std::isfinite(s.velocity.vx_mps) &&
         std::isfinite(s.velocity.vy_mps) && std::isfinite(s.velocity.vz_mps);
}

bool between(double v, double a, double b) {
  const double slack = 1e-6 + 1e-12 * std::max(std::fabs(a), std::fabs(b));
  return v >= std::min(a, b) - slack && v <= std::max(a, b) + slack;
}

/// The checks every parse result must pass; returns the number of knots.
std::size_t check_result(const TraceParseResult& r, const LineCounts& lines, bool ns2) {
  FUZZ_CHECK(r.bad_lines <= lines.content, "%zu bad lines of %zu", r.bad_lines, lines.content);
  FUZZ_CHECK(r.errors.size() == std::min(r.bad_lines, TraceParseResult::kMaxReportedErrors),
             "%zu errors kept for %zu bad lines", r.errors.size(), r.bad_lines);
  for (std::size_t i = 0; i < r.errors.size(); ++i) {
    const TraceLineError& e = r.errors[i];
    FUZZ_CHECK(e.line >= 1 && e.line <= lines.lines, "error line %zu of %zu", e.line, lines.lines);
    FUZZ_CHECK(i == 0 || e.line > r.errors[i - 1].line, "line %zu reported twice or out of order",
               e.line);
    FUZZ_CHECK(!e.reason.empty(), "no reason for line %zu", e.line);
  }
  std::size_t knots_total = 0;
  for (const auto& [node, track] : r.tracks) {
    FUZZ_CHECK(node <= TraceParseResult::kMaxNode, "node %u", node);
    FUZZ_CHECK(!track.empty(), "node %u has an empty track", node);
    const auto& k = track.knots();
    knots_total += k.size();
    if (ns2) FUZZ_CHECK(k.front().time_s == 0.0, "ns-2 track starts at %.17g", k.front().time_s);
    std::size_t cursor = 0;
    for (std::size_t i = 0; i < k.size(); ++i) {
      // An ns-2 leg may end after the last time the file names: slow, not unbounded.
      FUZZ_CHECK(std::isfinite(k[i].time_s) && k[i].time_s >= 0 &&
                     (ns2 || k[i].time_s <= TraceParseResult::kMaxTraceTimeS),
                 "knot time %.17g", k[i].time_s);
      FUZZ_CHECK(local_coordinate_error(k[i].position).empty(), "knot %zu: %s", i,
                 local_coordinate_error(k[i].position).c_str());
      FUZZ_CHECK(i == 0 || k[i].time_s >= k[i - 1].time_s, "knot times decrease at %zu", i);
      const bool last_of_its_time = i + 1 == k.size() || k[i + 1].time_s > k[i].time_s;
      if (!last_of_its_time) continue;
      const MotionState at = track.state_at(k[i].time_s, cursor);
      FUZZ_CHECK(equal(at.position, k[i].position), "node %u not at knot %zu at its time", node, i);
      FUZZ_CHECK(finite(at), "node %u: state at knot %zu not finite", node, i);
      if (i + 1 == k.size()) continue;
      const TrackKnot& b = k[i + 1];
      const MotionState mid = track.state_at(k[i].time_s + (b.time_s - k[i].time_s) / 3, cursor);
      FUZZ_CHECK(finite(mid), "node %u: state between knots %zu and %zu not finite", node, i,
                 i + 1);
      FUZZ_CHECK(between(mid.position.x_m, k[i].position.x_m, b.position.x_m) &&
                     between(mid.position.y_m, k[i].position.y_m, b.position.y_m) &&
                     between(mid.position.z_m, k[i].position.z_m, b.position.z_m),
                 "node %u: between knots %zu and %zu, off the segment", node, i, i + 1);
      if (ns2) FUZZ_CHECK(mid.velocity.vz_mps == 0.0, "ns-2 node %u climbs", node);
    }
    const MotionState before = track.state_at(k.front().time_s - 1.0, cursor);
    const MotionState after = track.state_at(k.back().time_s + 1.0, cursor);
    FUZZ_CHECK(
        equal(before.position, k.front().position) && equal(after.position, k.back().position),
        "node %u does not hold its ends", node);
    FUZZ_CHECK(before.velocity.vx_mps == 0 && after.velocity.vx_mps == 0 &&
                   before.velocity.vy_mps == 0 && after.velocity.vy_mps == 0,
               "node %u moves outside its track", node);
  }
  return knots_total;
}

bool same(const TraceParseResult& a, const TraceParseResult& b) {
  if (a.bad_lines != b.bad_lines || a.errors.size() != b.errors.size() ||
      a.tracks.size() != b.tracks.size())
    return false;
  for (std::size_t i = 0; i < a.errors.size(); ++i) {
    if (a.errors[i].line != b.errors[i].line || a.errors[i].reason != b.errors[i].reason)
      return false;
  }
  for (auto i = a.tracks.begin(), j = b.tracks.begin(); i != a.tracks.end(); ++i, ++j) {
    const auto& ka = i->second.knots();
    const auto& kb = j->second.knots();
    if (i->first != j->first || ka.size() != kb.size()) return false;
    for (std::size_t n = 0; n < ka.size(); ++n) {
      if (ka[n].time_s != kb[n].time_s || !same_bits(ka[n].position, kb[n].position)) return false;
    }
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const CsvTraceOptions options{GeodeticPosition{43.0008, -78.789, 180.0},
                                (data[0] & 1) ? CsvCoordinates::kGeodetic : CsvCoordinates::kLocal};
  // Its own allocation, so ASan sees a read past the end.
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  const LineCounts lines = count_lines(text);

  const TraceParseResult csv = parse_csv_trace(text, "fuzz.csv", options);
  const std::size_t samples = check_result(csv, lines, false);
  const bool unknown_header =
      !csv.errors.empty() && csv.errors.front().reason.starts_with("unknown header");
  if (unknown_header) {
    FUZZ_CHECK(csv.bad_lines == 1 && csv.tracks.empty(), "unknown header, yet %zu bad lines",
               csv.bad_lines);
  } else {
    const std::size_t read = samples + csv.bad_lines;
    FUZZ_CHECK(read == lines.content || read + 1 == lines.content,
               "%zu samples + %zu bad lines for %zu lines with content", samples, csv.bad_lines,
               lines.content);
  }
  FUZZ_CHECK(same(csv, parse_csv_trace(text, "fuzz.csv", options)), "CSV not deterministic");

  const TraceParseResult ns2 = parse_ns2_trace(text, "fuzz.tcl");
  check_result(ns2, lines, true);
  FUZZ_CHECK(same(ns2, parse_ns2_trace(text, "fuzz.tcl")), "ns-2 not deterministic");
  return 0;
}
