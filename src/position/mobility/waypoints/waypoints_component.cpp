// The mobility model "waypoints": a path through given points, straight legs by time or by speed.
#include <algorithm>
#include <limits>
#include <optional>
#include <string_view>
#include <variant>
#include <vector>

#include "../component_support.hpp"
#include "rfsitl/position/mobility/waypoint_model.hpp"

namespace rfsitl::position::mobility {
namespace {

using namespace detail;

// A waypoint as a scenario writes it: x/y/z or lat/lon/alt, and the time `t`
// it is reached or the `speed_mps` of the leg that reaches it. Position and
// timing fields are optional so that the rule can tell which form was given.
struct WaypointItem {
  std::optional<double> t, x, y, z, lat, lon, alt, speed_mps;
  double dwell_s = 0;
};

const config::RecordFields<WaypointItem>& waypoint_item_fields() {
  using P = WaypointItem;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  static const auto f =
      config::RecordFields<P>()
          .real("t", &P::t, "s", {0, kInf},
                "arrival time (virtual); the first point's is 0 if left out")
          .real("x", &P::x, "m", kEastNorth, "east of channel.origin")
          .real("y", &P::y, "m", kEastNorth, "north of channel.origin")
          .real("z", &P::z, "m", kHeight, "up from channel.origin; 0 if left out")
          .real("lat", &P::lat, "deg", {kLatitudeLimit.lo, kLatitudeLimit.hi}, "WGS84 latitude")
          .real("lon", &P::lon, "deg", {kLongitudeLimit.lo, kLongitudeLimit.hi}, "WGS84 longitude")
          .real("alt", &P::alt, "m", kHeight, "above the WGS84 ellipsoid; 0 if left out")
          .real("speed_mps", &P::speed_mps, "m/s", {0, 1e4, true},
                "instead of t: the speed of the straight leg from the previous point")
          .real("dwell_s", &P::dwell_s, "s", {0, kInf}, "time spent at the point before leaving");
  return f;
}

// One item as the model's Waypoint. Throws SettingError naming the item (or
// its field) when it gives neither or both forms of its position or timing.
Waypoint to_waypoint(const WaypointItem& p, std::size_t i) {
  const std::string at = "points[" + std::to_string(i) + "]";
  const bool geodetic = p.lat || p.lon || p.alt;
  if (geodetic && (p.x || p.y || p.z)) {
    throw config::SettingError(at, "mixes lat/lon/alt with x/y/z; use one form");
  }
  if (geodetic ? !(p.lat && p.lon) : !(p.x && p.y)) {
    throw config::SettingError(
        at, "needs x and y (z defaults to 0) or lat and lon (alt defaults to 0)");
  }
  if (p.t && p.speed_mps) {
    throw config::SettingError(at + ".speed_mps",
                               "conflicts with t; give the arrival time or the leg's speed");
  }
  if (i == 0 && p.speed_mps) {
    throw config::SettingError(at + ".speed_mps",
                               "not allowed on the first point: no leg arrives at it");
  }
  if (i > 0 && !p.t && !p.speed_mps) {
    throw config::SettingError(at, "needs t (arrival time) or speed_mps (the leg's speed)");
  }
  Waypoint w;
  if (geodetic) {
    w.point = GeodeticPosition{*p.lat, *p.lon, p.alt.value_or(0.0)};
  } else {
    w.point = LocalPosition{*p.x, *p.y, p.z.value_or(0.0)};
  }
  w.time_s = p.t;
  w.speed_mps = p.speed_mps;
  w.dwell_s = p.dwell_s;
  return w;
}

struct WaypointFields {
  std::vector<WaypointItem> points;
  bool loop = false;

  WaypointSettings model() const {
    WaypointSettings s;
    for (std::size_t i = 0; i < points.size(); ++i) s.points.push_back(to_waypoint(points[i], i));
    s.loop = loop;
    return s;
  }
};

// The model calls a point's time `time_s` and its position `point`; a
// scenario's item calls them `t` and the item itself.
config::SettingError waypoint_error(const std::invalid_argument& e) {
  const config::SettingError s = setting_error(e);
  std::string key = s.key();
  const auto ends_with = [&key](std::string_view tail) {
    return key.size() >= tail.size() &&
           key.compare(key.size() - tail.size(), tail.size(), tail) == 0;
  };
  if (ends_with(".time_s")) key.replace(key.size() - 6, 6, "t");
  if (ends_with(".point")) key.resize(key.size() - 6);
  return {key, s.what()};
}

// At load time, the model's own checks too (times in order, legs that take
// time, a closed loop), so that their errors name a line. They need a frame:
// distances between two lat/lon points are the same in any local frame (the
// conversion is exact, through ECEF), so a frame at the first point stands in
// for channel.origin, which a rule cannot see. A path that mixes both forms
// has legs that depend on channel.origin: the engine checks those when it
// builds the model.
void check_waypoints(const WaypointFields& f) {
  const WaypointSettings s = f.model();
  const auto is_geodetic = [](const Waypoint& w) {
    return std::holds_alternative<GeodeticPosition>(w.point);
  };
  const std::size_t geodetic = std::count_if(s.points.begin(), s.points.end(), is_geodetic);
  try {
    if (geodetic != 0 && geodetic != s.points.size()) {
      s.validate();
    } else {
      GeodeticPosition frame;  // any will do for x/y/z points: they are taken as they are
      if (geodetic != 0) frame = std::get<GeodeticPosition>(s.points.front().point);
      const WaypointModel model(s, frame);
    }
  } catch (const std::invalid_argument& e) {
    throw waypoint_error(e);
  }
}

const config::Fields<WaypointFields>& waypoint_fields() {
  using S = WaypointFields;
  static const auto f =
      config::Fields<S>()
          .records("points", &S::points, waypoint_item_fields(), 1, 100000,
                   "the path: x/y/z or lat/lon/alt, each with t or speed_mps")
          .flag("loop", &S::loop, "repeat the path forever; its last point must be its first")
          .rule(check_waypoints);
  return f;
}

}  // namespace

MobilityComponent waypoints_component() {
  return {
      waypoint_fields().info("mobility", "waypoints",
                             "a path through given points: straight legs, by time or by speed"),
      [](const config::Settings& s, const MobilityContext& c) -> std::unique_ptr<MobilityModel> {
        return std::make_unique<WaypointModel>(waypoint_fields().build(s).model(), c.origin);
      }};
}

}  // namespace rfsitl::position::mobility
