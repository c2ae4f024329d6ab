/// Location ports: parse_location_line on arbitrary text, cut into lines at
/// '\n' as the port does (the parser's precondition: no newline in a line).
///
/// Checks, per line:
///  - exactly one outcome: a position, a non-empty error, or blank;
///  - blank exactly when the line is empty or whitespace only;
///  - a geodetic position is finite with |lat| <= 90, |lon| <= 180 and
///    -1000 <= alt <= 100000 m; a local one is finite with -1000 <= z <= 100000;
///  - the error is never the parser's "internal error" fallback (an exception
///    it did not expect);
///  - parsing is deterministic (the same line twice gives the same result).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <variant>

#include "fuzz_check.hpp"
#include "rfsitl/position/location_port/location_line.hpp"

using rfsitl::GeodeticPosition;
using rfsitl::LocalPosition;
using rfsitl::position::LocationParseResult;

namespace {

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

bool same(const LocationParseResult& a, const LocationParseResult& b) {
  if (a.blank != b.blank || a.error != b.error || a.position.has_value() != b.position.has_value())
    return false;
  if (!a.position) return true;
  if (a.position->index() != b.position->index()) return false;
  // Bitwise: the parser must not depend on anything but the line.
  if (const auto* g = std::get_if<GeodeticPosition>(&*a.position)) {
    const auto& h = std::get<GeodeticPosition>(*b.position);
    return std::memcmp(g, &h, sizeof *g) == 0;
  }
  const auto& l = std::get<LocalPosition>(*a.position);
  const auto& m = std::get<LocalPosition>(*b.position);
  return std::memcmp(&l, &m, sizeof l) == 0;
}

void check_line(std::string_view line) {
  const LocationParseResult r = rfsitl::position::parse_location_line(line);
  const int outcomes = (r.position ? 1 : 0) + (r.error.empty() ? 0 : 1) + (r.blank ? 1 : 0);
  FUZZ_CHECK(outcomes == 1, "%d outcomes (position %d, error '%s', blank %d)", outcomes,
             r.position.has_value(), r.error.c_str(), r.blank);
  bool all_space = true;
  for (const char c : line) all_space = all_space && is_space(c);
  FUZZ_CHECK(r.blank == all_space, "blank %d for a line that is%s all whitespace", r.blank,
             all_space ? "" : " not");
  FUZZ_CHECK(r.error.rfind("internal error", 0) != 0, "%s", r.error.c_str());
  if (r.position) {
    if (const auto* g = std::get_if<GeodeticPosition>(&*r.position)) {
      FUZZ_CHECK(std::isfinite(g->lat_deg) && std::isfinite(g->lon_deg) && std::isfinite(g->alt_m),
                 "non-finite geodetic position");
      FUZZ_CHECK(std::fabs(g->lat_deg) <= 90.0 && std::fabs(g->lon_deg) <= 180.0 &&
                     g->alt_m >= -1000.0 && g->alt_m <= 100000.0,
                 "out of range: lat %.17g lon %.17g alt %.17g", g->lat_deg, g->lon_deg, g->alt_m);
    } else {
      const auto& l = std::get<LocalPosition>(*r.position);
      FUZZ_CHECK(std::isfinite(l.x_m) && std::isfinite(l.y_m) && std::isfinite(l.z_m),
                 "non-finite local position %.17g %.17g %.17g", l.x_m, l.y_m, l.z_m);
      FUZZ_CHECK(l.z_m >= -1000.0 && l.z_m <= 100000.0, "local z %.17g out of range", l.z_m);
    }
  }
  FUZZ_CHECK(same(r, rfsitl::position::parse_location_line(line)), "not deterministic");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t nl = text.find('\n', start);
    const std::size_t end = nl == std::string_view::npos ? text.size() : nl;
    // Each line in its own allocation so ASan sees reads past its end.
    const std::string line(text.substr(start, end - start));
    check_line(line);
    if (nl == std::string_view::npos) break;
    start = nl + 1;
  }
  return 0;
}
