/// Antenna pattern files: antenna::parse_pattern on arbitrary text.
///
/// Checks:
///  - the only exception that leaves parse_pattern is std::invalid_argument
///    (its contract), and its what() is "fuzz.csv:<line>: <reason>" with the
///    line within the text (1 .. newlines + 1) and a reason;
///  - a grid it accepts is what the format promises: azimuths strictly
///    increasing from 0 to 360, elevations strictly increasing from -90 to 90,
///    at least 2 of each, every gain finite within [-200, 100] dBi and the 360
///    column equal to column 0;
///  - the look-up returns each grid point's own gain, and between grid points
///    (and for angles out of range, which it clamps) a finite gain within the
///    table's least and greatest.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_check.hpp"
#include "rfsitl/channel/stages/antenna.hpp"

using rfsitl::channel::antenna::PatternGrid;

namespace {

void check_refusal(const std::string& what, const std::string& source, std::string_view text) {
  FUZZ_CHECK(what.rfind(source + ":", 0) == 0, "error does not name the source: %s", what.c_str());
  std::size_t at = source.size() + 1;
  std::size_t line = 0;
  while (at < what.size() && what[at] >= '0' && what[at] <= '9' && line < 1'000'000'000) {
    line = line * 10 + static_cast<std::size_t>(what[at++] - '0');
  }
  const auto lines = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
  FUZZ_CHECK(line >= 1 && line <= lines, "line %zu outside 1..%zu: %s", line, lines, what.c_str());
  FUZZ_CHECK(what.compare(at, 2, ": ") == 0 && what.size() > at + 2, "no reason: %s", what.c_str());
}

void check_axis(const std::vector<double>& axis, double first, double last, const char* name) {
  FUZZ_CHECK(axis.size() >= 2, "%s: %zu values", name, axis.size());
  FUZZ_CHECK(axis.front() == first && axis.back() == last, "%s: %g .. %g", name, axis.front(),
             axis.back());
  for (std::size_t i = 1; i < axis.size(); ++i) {
    FUZZ_CHECK(axis[i] > axis[i - 1], "%s: %g after %g", name, axis[i], axis[i - 1]);
  }
}

void check_grid(const PatternGrid& g) {
  const auto& az = g.azimuths_deg();
  const auto& el = g.elevations_deg();
  check_axis(az, 0.0, 360.0, "azimuths");
  check_axis(el, -90.0, 90.0, "elevations");
  double least = 1e300;
  double greatest = -1e300;
  for (std::size_t r = 0; r < el.size(); ++r) {
    FUZZ_CHECK(g.at(r, az.size() - 1) == g.at(r, 0), "row %zu: 360 is not 0 again", r);
    for (std::size_t c = 0; c < az.size(); ++c) {
      const double v = g.at(r, c);
      FUZZ_CHECK(std::isfinite(v) && v >= -200.0 && v <= 100.0, "gain %g", v);
      least = std::min(least, v);
      greatest = std::max(greatest, v);
      const double looked_up = g.gain_dbi(az[c], el[r]);
      FUZZ_CHECK(std::abs(looked_up - v) <= 1e-9, "grid point (%zu, %zu): %g, table %g", r, c,
                 looked_up, v);
    }
  }
  // Between grid points, and angles out of range (clamped).
  for (const double a : {-10.0, 0.5, 91.25, 179.999, 359.9999, 400.0}) {
    for (const double e : {-95.0, -89.9, -12.5, 0.0, 33.3, 90.0, 120.0}) {
      const double v = g.gain_dbi(a, e);
      FUZZ_CHECK(std::isfinite(v) && v >= least - 1e-9 && v <= greatest + 1e-9,
                 "gain %g at (%g, %g) outside [%g, %g]", v, a, e, least, greatest);
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // A copy of exactly `size` bytes (no terminator the parser could rely on).
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::string source = "fuzz.csv";
  try {
    check_grid(rfsitl::channel::antenna::parse_pattern(std::string_view(text), source));
  } catch (const std::invalid_argument& e) {
    check_refusal(e.what(), source, text);
  } catch (const std::exception& e) {
    FUZZ_CHECK(false, "parse_pattern threw something other than invalid_argument: %s", e.what());
  }
  return 0;
}
