#include "rfsitl/monitor/position_request.hpp"

#include "rfsitl/common/position_limits.hpp"

namespace rfsitl::monitor {
namespace {

/// The number under `key`, `fallback` when absent (and allowed to be), or
/// nullopt with `error` set. Never lets the JSON library's own messages out.
std::optional<double> number(const nlohmann::json& body, const char* key,
                             std::optional<double> fallback, std::string& error) {
  const auto it = body.find(key);
  if (it == body.end()) {
    if (!fallback) error = std::string(key) + ": missing (expected a number)";
    return fallback;
  }
  if (!it->is_number()) {
    error = std::string(key) + ": expected a number";
    return std::nullopt;
  }
  return it->get<double>();
}

}  // namespace

PositionRequest read_position_request(const nlohmann::json& body, double default_z_m,
                                      double default_alt_m) {
  PositionRequest r;
  if (!body.is_object()) {
    r.error = "expected a JSON object with x, y[, z] or lat, lon[, alt]";
    return r;
  }
  const bool geodetic = body.contains("lat") || body.contains("lon") || body.contains("alt");
  const bool local = body.contains("x") || body.contains("y") || body.contains("z");
  if (geodetic && local) {
    r.error = "mixes lat/lon/alt with x/y/z: use one or the other";
    return r;
  }
  if (!geodetic && !local) {
    r.error = "no position: expected x, y[, z] (metres) or lat, lon[, alt]";
    return r;
  }
  Position p;
  if (geodetic) {
    const auto lat = number(body, "lat", std::nullopt, r.error);
    if (!lat) return r;
    const auto lon = number(body, "lon", std::nullopt, r.error);
    if (!lon) return r;
    const auto alt = number(body, "alt", default_alt_m, r.error);
    if (!alt) return r;
    p = GeodeticPosition{*lat, *lon, *alt};
  } else {
    const auto x = number(body, "x", std::nullopt, r.error);
    if (!x) return r;
    const auto y = number(body, "y", std::nullopt, r.error);
    if (!y) return r;
    const auto z = number(body, "z", default_z_m, r.error);
    if (!z) return r;
    p = LocalPosition{*x, *y, *z};
  }
  r.error = position_error(p);
  if (r.error.empty()) r.position = p;
  return r;
}

}  // namespace rfsitl::monitor
