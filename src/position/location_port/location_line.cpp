#include "rfsitl/position/location_port/location_line.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <exception>
#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

#include "rfsitl/common/position_limits.hpp"

namespace rfsitl::position {
namespace {

// Every rejection is reported as this exception inside the parser and turned into
// LocationParseResult::error at the single entry point; it never leaves this file.
struct BadLine {
  std::string reason;
};

[[noreturn]] void fail(std::string reason) {
  throw BadLine{std::move(reason)};
}

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

// Parses a whole token as a decimal number; nullopt if any character is left over.
// std::from_chars does not accept a leading '+', which some feeds write.
std::optional<double> to_double(std::string_view s) {
  if (s.size() > 1 && s.front() == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
  double v = 0.0;
  const auto res = std::from_chars(s.data(), s.data() + s.size(), v);
  if (res.ec != std::errc{} || res.ptr != s.data() + s.size()) return std::nullopt;
  return v;
}

// The limits are the shared ones (rfsitl/common/position_limits.hpp), so the
// dashboard and scenario files refuse exactly what this port refuses.
Position checked(const Position& p) {
  if (std::string why = position_error(p); !why.empty()) fail(std::move(why));
  return p;
}

GeodeticPosition checked_geodetic(double lat, double lon, double alt) {
  return std::get<GeodeticPosition>(checked(GeodeticPosition{lat, lon, alt}));
}

// ---- "lat lon alt" ---------------------------------------------------------------

// Fields are separated by whitespace and/or one comma; two commas in a row would
// mean an empty field, which is more likely a broken feed than intent.
Position parse_plain(std::string_view line) {
  std::vector<std::string_view> fields;
  bool comma_pending = true;  // a comma before the first field is also an empty field
  std::size_t i = 0;
  while (i < line.size()) {
    if (is_space(line[i])) {
      ++i;
    } else if (line[i] == ',') {
      if (comma_pending) fail("empty field " + std::to_string(fields.size() + 1));
      comma_pending = true;
      ++i;
    } else {
      std::size_t end = i;
      while (end < line.size() && !is_space(line[end]) && line[end] != ',') ++end;
      fields.push_back(line.substr(i, end - i));
      comma_pending = false;
      i = end;
    }
  }
  if (comma_pending) fail("empty field " + std::to_string(fields.size() + 1));
  if (fields.size() != 3) {
    fail("expected 3 numbers (lat lon alt), got " + std::to_string(fields.size()));
  }
  static constexpr const char* kNames[3] = {"latitude", "longitude", "altitude"};
  double v[3];
  for (std::size_t k = 0; k < 3; ++k) {
    const auto parsed = to_double(fields[k]);
    if (!parsed) fail(std::string(kNames[k]) + " '" + std::string(fields[k]) + "' is not a number");
    v[k] = *parsed;
  }
  return checked_geodetic(v[0], v[1], v[2]);
}

// ---- JSON ------------------------------------------------------------------------

// Value of `key` as a number; `fallback` when absent and optional.
double json_number(const nlohmann::json& obj, const char* key, std::optional<double> fallback) {
  const auto it = obj.find(key);
  if (it == obj.end()) {
    if (!fallback) fail(std::string("JSON object missing key \"") + key + "\"");
    return *fallback;
  }
  if (!it->is_number()) fail(std::string("JSON key \"") + key + "\" is not a number");
  return it->get<double>();
}

Position parse_json(std::string_view line) {
  nlohmann::json obj;
  try {
    obj = nlohmann::json::parse(line);
  } catch (const nlohmann::json::parse_error& e) {
    fail("malformed JSON (syntax error at byte " + std::to_string(e.byte) + ")");
  } catch (const nlohmann::json::out_of_range&) {
    fail("JSON number out of range");  // e.g. 1e999, which no double can hold
  }
  if (!obj.is_object()) fail("JSON value is not an object");

  const bool geodetic = obj.contains("lat") || obj.contains("lon") || obj.contains("alt");
  const bool local = obj.contains("x") || obj.contains("y") || obj.contains("z");
  if (geodetic && local) fail("JSON object mixes lat/lon/alt with x/y/z keys");
  if (geodetic) {
    const double lat = json_number(obj, "lat", std::nullopt);
    const double lon = json_number(obj, "lon", std::nullopt);
    const double alt = json_number(obj, "alt", 0.0);
    return checked_geodetic(lat, lon, alt);
  }
  if (local) {
    const double x = json_number(obj, "x", std::nullopt);
    const double y = json_number(obj, "y", std::nullopt);
    const double z = json_number(obj, "z", 0.0);
    // z is height above the scenario origin; the altitude bounds apply to it too.
    return checked(LocalPosition{x, y, z});
  }
  fail("JSON object has neither lat/lon/alt nor x/y/z keys");
}

// ---- NMEA 0183 GGA -----------------------------------------------------------------

std::string hex_byte(unsigned v) {
  static constexpr char kDigits[] = "0123456789ABCDEF";
  return {kDigits[(v >> 4) & 0xF], kDigits[v & 0xF]};
}

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

bool all_digits(std::string_view s) {
  for (char c : s) {
    if (c < '0' || c > '9') return false;
  }
  return !s.empty();
}

// "ddmm.mmmm" (latitude, max_deg_digits 2) or "dddmm.mmmm" (longitude, 3) plus the
// hemisphere letter; returns signed decimal degrees.
double nmea_angle(std::string_view value, std::string_view hemisphere, const char* name,
                  int max_deg_digits, char positive, char negative) {
  if (value.empty()) fail(std::string("NMEA GGA ") + name + " field is empty");
  const std::size_t dot = std::min(value.find('.'), value.size());
  const std::string_view int_part = value.substr(0, dot);
  const std::string_view frac_part = dot < value.size() ? value.substr(dot + 1) : "";
  const bool well_formed = all_digits(int_part) && int_part.size() >= 3 &&
                           int_part.size() <= static_cast<std::size_t>(max_deg_digits) + 2 &&
                           (dot == value.size() || all_digits(frac_part));
  if (!well_formed) {
    fail(std::string("NMEA GGA ") + name + " '" + std::string(value) + "' is not " +
         (max_deg_digits == 2 ? "ddmm.mmmm" : "dddmm.mmmm"));
  }
  const std::size_t deg_digits = int_part.size() - 2;
  const double degrees = *to_double(int_part.substr(0, deg_digits));
  const double minutes = *to_double(value.substr(deg_digits));
  if (minutes >= 60.0) {
    fail(std::string("NMEA GGA ") + name + " minutes " + format_coordinate(minutes) +
         " out of range [0, 60)");
  }
  double deg = degrees + minutes / 60.0;
  if (hemisphere.size() == 1 && hemisphere[0] == negative) {
    deg = -deg;
  } else if (hemisphere.size() != 1 || hemisphere[0] != positive) {
    fail(std::string("NMEA GGA ") + name + " hemisphere '" + std::string(hemisphere) + "' is not " +
         positive + " or " + negative);
  }
  return deg;
}

// A height field and its unit field; `optional_empty` lets an unknown (empty)
// geoid separation count as 0, as some receivers leave it blank.
double nmea_height(std::string_view value, std::string_view unit, const char* name,
                   bool optional_empty) {
  if (value.empty()) {
    if (optional_empty) return 0.0;
    fail(std::string("NMEA GGA ") + name + " field is empty");
  }
  const auto v = to_double(value);
  if (!v) fail(std::string("NMEA GGA ") + name + " '" + std::string(value) + "' is not a number");
  if (unit != "M") {
    fail(std::string("NMEA GGA ") + name + " unit '" + std::string(unit) + "' is not M");
  }
  return *v;
}

Position parse_nmea(std::string_view line) {
  // Checksum: XOR of every character between '$' and '*', written as two hex digits.
  const std::size_t star = line.rfind('*');
  if (star == std::string_view::npos) fail("NMEA sentence without checksum");
  const std::string_view body = line.substr(1, star - 1);
  const std::string_view given = line.substr(star + 1);
  if (given.size() != 2 || hex_digit(given[0]) < 0 || hex_digit(given[1]) < 0) {
    fail("NMEA checksum '" + std::string(given) + "' is not two hex digits");
  }
  unsigned computed = 0;
  for (char c : body) computed ^= static_cast<unsigned char>(c);
  const auto expected = static_cast<unsigned>(hex_digit(given[0]) * 16 + hex_digit(given[1]));
  if (computed != expected) {
    fail("NMEA checksum mismatch: computed " + hex_byte(computed) + ", line says " +
         hex_byte(expected));
  }

  std::vector<std::string_view> f;
  for (std::size_t start = 0;;) {
    const std::size_t comma = body.find(',', start);
    f.push_back(body.substr(start, comma == std::string_view::npos ? body.npos : comma - start));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  // Address: a 2-letter talker (GP, GN, GL, GA, ...) and the sentence type.
  const std::string_view address = f[0];
  const bool letter_talker = address.size() == 5 && address[0] >= 'A' && address[0] <= 'Z' &&
                             address[1] >= 'A' && address[1] <= 'Z';
  if (!letter_talker || address.substr(2) != "GGA") {
    fail("unsupported NMEA sentence " + (address.empty() ? "(no address)" : std::string(address)));
  }
  // time, lat, N/S, lon, E/W, quality, sats, hdop, alt, M, geoid sep, M [, age, station]
  if (f.size() < 13) {
    fail("NMEA GGA sentence has " + std::to_string(f.size()) + " fields, expected 15");
  }
  // Quality first: without a fix the position fields are usually empty, and
  // "no fix" is the useful reason.
  const std::string_view quality = f[6];
  if (!all_digits(quality)) {
    fail("NMEA GGA fix quality '" + std::string(quality) + "' is not a number");
  }
  if (quality.find_first_not_of('0') == std::string_view::npos) {
    fail("NMEA GGA fix quality 0 (no fix)");
  }
  const double lat = nmea_angle(f[2], f[3], "latitude", 2, 'N', 'S');
  const double lon = nmea_angle(f[4], f[5], "longitude", 3, 'E', 'W');
  const double msl = nmea_height(f[9], f[10], "altitude", false);
  const double geoid = nmea_height(f[11], f[12], "geoid separation", true);
  return checked_geodetic(lat, lon, msl + geoid);
}

}  // namespace

LocationParseResult parse_location_line(std::string_view line) {
  LocationParseResult result;
  const std::string_view text = trim(line);
  if (text.empty()) {
    result.blank = true;
    return result;
  }
  try {
    // '[' goes to JSON too, so an array is reported as "not an object" rather
    // than as a strange number.
    if (text.front() == '{' || text.front() == '[') {
      result.position = parse_json(text);
    } else if (text.front() == '$') {
      result.position = parse_nmea(text);
    } else {
      result.position = parse_plain(text);
    }
  } catch (const BadLine& bad) {
    result.error = bad.reason;
  } catch (const std::exception& e) {
    // Not expected (e.g. allocation failure); the feed must survive it anyway.
    result.error = std::string("internal error: ") + e.what();
  } catch (...) {
    result.error = "internal error";
  }
  return result;
}

}  // namespace rfsitl::position
