// The registered mobility models and their declared settings. Each model's own
// settings struct nests a box or optional parts; the flat structs here are what
// a scenario writes, one key per field.
#include <algorithm>
#include <filesystem>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "rfsitl/common/position_limits.hpp"
#include "rfsitl/common/xoshiro256.hpp"
#include "rfsitl/config/fields.hpp"
#include "rfsitl/position/mobility/csv_trace.hpp"
#include "rfsitl/position/mobility/gauss_markov_model.hpp"
#include "rfsitl/position/mobility/mobility_component.hpp"
#include "rfsitl/position/mobility/ns2_trace.hpp"
#include "rfsitl/position/mobility/orbit_model.hpp"
#include "rfsitl/position/mobility/random_waypoint_model.hpp"
#include "rfsitl/position/mobility/trace_replay_model.hpp"
#include "rfsitl/position/mobility/waypoint_model.hpp"

namespace rfsitl::position::mobility {
namespace {

// A model says "<model>.<field> must be ..." (or "<model>.<field>: why"); as a
// SettingError it names the field, so that the scenario reader can point at its line.
config::SettingError setting_error(const std::invalid_argument& e) {
  const std::string what = e.what();
  const auto dot = what.find('.');
  const auto space = what.find(' ', dot);
  if (dot == std::string::npos || space == std::string::npos) return {"", what};
  std::string key = what.substr(dot + 1, space - dot - 1);
  if (!key.empty() && key.back() == ':') key.pop_back();
  return {key, what.substr(space + 1)};
}

template <typename Settings>
void checked(const Settings& s) {
  try {
    s.validate();
  } catch (const std::invalid_argument& e) {
    throw setting_error(e);
  }
}

// Seed 0: each node its own track, from the scenario's seed and the node id.
std::uint64_t node_seed(std::uint64_t seed, const MobilityContext& c) {
  if (seed != 0) return seed;
  std::uint64_t state = c.scenario_seed + 0x9E3779B97F4A7C15ULL * c.node;
  return splitmix64(state);
}

// The limits every input of positions accepts (common/position_limits.hpp).
constexpr config::Range kEastNorth{kHorizontalLimit.lo, kHorizontalLimit.hi};
constexpr config::Range kHeight{kAltitudeLimit.lo, kAltitudeLimit.hi};

const config::Fields<OrbitSettings>& orbit_fields() {
  using S = OrbitSettings;
  static const auto f =
      config::Fields<S>()
          .real("centre_x_m", &S::centre_x_m, "m", kEastNorth, "centre, east")
          .real("centre_y_m", &S::centre_y_m, "m", kEastNorth, "centre, north")
          .real("radius_m", &S::radius_m, "m", {0, kHorizontalLimit.hi, true}, "radius")
          .real("speed_mps", &S::speed_mps, "m/s", {-1e4, 1e4},
                "ground speed; positive counter-clockwise seen from above")
          .real("altitude_m", &S::altitude_m, "m", kHeight, "local z")
          .real("phase_rad", &S::phase_rad, "rad", {-1e3, 1e3},
                "angle at t = 0, counter-clockwise from east of the centre")
          .rule(checked<S>);
  return f;
}

// Random waypoint and Gauss-Markov share their box, seed and start.
struct BoxFields {
  double x_min_m = -100, x_max_m = 100, y_min_m = -100, y_max_m = 100, z_min_m = 10, z_max_m = 30;
  std::uint64_t seed = 0;

  /// A model's settings with the box, the node's seed and, when the node's
  /// scenario position lies in the box, its start.
  template <typename Model>
  Model with_shared(Model s, const MobilityContext& c) const {
    s.box = {x_min_m, x_max_m, y_min_m, y_max_m, z_min_m, z_max_m};
    s.seed = node_seed(seed, c);
    if (c.start && s.box.contains(*c.start)) s.start = c.start;
    return s;
  }
};

template <typename S>
config::Fields<S> with_box() {
  // The box's members belong to the base; as members of S they bind to S's fields.
  const auto m = [](double BoxFields::*member) { return static_cast<double S::*>(member); };
  return config::Fields<S>()
      .real("x_min_m", m(&BoxFields::x_min_m), "m", kEastNorth, "box: least east")
      .real("x_max_m", m(&BoxFields::x_max_m), "m", kEastNorth, "box: most east")
      .real("y_min_m", m(&BoxFields::y_min_m), "m", kEastNorth, "box: least north")
      .real("y_max_m", m(&BoxFields::y_max_m), "m", kEastNorth, "box: most north")
      .real("z_min_m", m(&BoxFields::z_min_m), "m", kHeight, "box: lowest")
      .real("z_max_m", m(&BoxFields::z_max_m), "m", kHeight, "box: highest")
      .integer("seed", static_cast<std::uint64_t S::*>(&BoxFields::seed), "", 0, UINT64_MAX,
               "0: the scenario seed mixed with the node id");
}

struct RandomWaypointFields : BoxFields {
  double speed_min_mps = 1, speed_max_mps = 10, pause_s = 0;
  RandomWaypointSettings model(const MobilityContext& c) const {
    RandomWaypointSettings s;
    s.speed_min_mps = speed_min_mps;
    s.speed_max_mps = speed_max_mps;
    s.pause_s = pause_s;
    return with_shared(s, c);
  }
};

const config::Fields<RandomWaypointFields>& random_waypoint_fields() {
  using S = RandomWaypointFields;
  static const auto f =
      with_box<S>()
          .real("speed_min_mps", &S::speed_min_mps, "m/s", {0, 1e4, true}, "least leg speed")
          .real("speed_max_mps", &S::speed_max_mps, "m/s", {0, 1e4, true}, "greatest leg speed")
          .real("pause_s", &S::pause_s, "s", {0, 1e6}, "wait at each destination")
          .rule([](const S& s) { checked(s.model(MobilityContext{})); });
  return f;
}

struct GaussMarkovFields : BoxFields {
  double alpha = 0.85, mean_speed_mps = 10, mean_direction_rad = 0, speed_sd_mps = 2,
         direction_sd_rad = 0.5, update_interval_s = 1;
  GaussMarkovSettings model(const MobilityContext& c) const {
    GaussMarkovSettings s;
    s.alpha = alpha;
    s.mean_speed_mps = mean_speed_mps;
    s.mean_direction_rad = mean_direction_rad;
    s.speed_sd_mps = speed_sd_mps;
    s.direction_sd_rad = direction_sd_rad;
    s.update_interval_s = update_interval_s;
    return with_shared(s, c);
  }
};

const config::Fields<GaussMarkovFields>& gauss_markov_fields() {
  using S = GaussMarkovFields;
  static const auto f =
      with_box<S>()
          .real("alpha", &S::alpha, "", {0, 1}, "memory: 0 memoryless, 1 straight lines")
          .real("mean_speed_mps", &S::mean_speed_mps, "m/s", {0, 1e4}, "mean speed")
          .real("mean_direction_rad", &S::mean_direction_rad, "rad", {-10, 10},
                "mean heading, counter-clockwise from east")
          .real("speed_sd_mps", &S::speed_sd_mps, "m/s", {0, 1e4}, "speed standard deviation")
          .real("direction_sd_rad", &S::direction_sd_rad, "rad", {0, 10},
                "heading standard deviation")
          .real("update_interval_s", &S::update_interval_s, "s", {0, 1e6, true},
                "time between redraws of speed and heading")
          .rule([](const S& s) { checked(s.model(MobilityContext{})); });
  return f;
}

struct TraceFields {
  std::string file;
  std::string format = "csv";
  std::string coordinates = "local";
  std::uint64_t node = 0;
};

const config::Fields<TraceFields>& trace_fields() {
  using S = TraceFields;
  static const auto f =
      config::Fields<S>()
          .text("file", &S::file, "trace file; relative to the scenario file's folder")
          .choice("format", &S::format, {"csv", "ns2"},
                  "csv: `t, node, x, y, z` or `t, node, lat, lon, alt`; ns2: setdest movement file")
          .choice("coordinates", &S::coordinates, {"local", "geodetic"},
                  "csv without a header line: x/y/z metres or lat/lon/alt")
          .integer("node", &S::node, "", 0, 65535, "the node number in the file; 0: this node's id")
          .rule([](const S& s) {
            if (s.file.empty()) throw config::SettingError("file", "required");
          });
  return f;
}

std::unique_ptr<MobilityModel> make_trace(const TraceFields& t, const MobilityContext& c) {
  std::filesystem::path path(t.file);
  if (path.is_relative() && !c.base_dir.empty()) path = std::filesystem::path(c.base_dir) / path;
  const TraceParseResult r =
      t.format == "ns2" ? read_ns2_trace(path.string())
                        : read_csv_trace(path.string(), {c.origin, t.coordinates == "geodetic"
                                                                       ? CsvCoordinates::kGeodetic
                                                                       : CsvCoordinates::kLocal});
  if (c.warn) {
    for (const auto& e : r.errors) c.warn(r.message(e));
    if (r.bad_lines > r.errors.size()) {
      c.warn(path.string() + ": " + std::to_string(r.bad_lines - r.errors.size()) +
             " more bad lines");
    }
  }
  const std::uint32_t wanted = t.node != 0 ? static_cast<std::uint32_t>(t.node) : c.node;
  const auto it = r.tracks.find(wanted);
  if (it == r.tracks.end()) {
    throw std::invalid_argument(path.string() + ": no track for node " + std::to_string(wanted));
  }
  return std::make_unique<TraceReplayModel>(it->second);
}

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

const std::vector<MobilityComponent>& mobility_components() {
  static const std::vector<MobilityComponent> all = {
      {gauss_markov_fields().info(
           "mobility", "gauss_markov",
           "Gauss-Markov: speed and heading with memory, reflected at a box"),
       [](const config::Settings& s, const MobilityContext& c) -> std::unique_ptr<MobilityModel> {
         return std::make_unique<GaussMarkovModel>(gauss_markov_fields().build(s).model(c));
       }},
      {orbit_fields().info("mobility", "orbit", "a circle at constant speed and altitude"),
       [](const config::Settings& s, const MobilityContext&) -> std::unique_ptr<MobilityModel> {
         return std::make_unique<OrbitModel>(orbit_fields().build(s));
       }},
      {random_waypoint_fields().info("mobility", "random_waypoint",
                                     "random waypoint in a box: legs at random speeds, pauses"),
       [](const config::Settings& s, const MobilityContext& c) -> std::unique_ptr<MobilityModel> {
         return std::make_unique<RandomWaypointModel>(random_waypoint_fields().build(s).model(c));
       }},
      {trace_fields().info("mobility", "trace", "replay of a CSV trace or an ns-2 setdest file"),
       [](const config::Settings& s, const MobilityContext& c) {
         return make_trace(trace_fields().build(s), c);
       }},
      {waypoint_fields().info("mobility", "waypoints",
                              "a path through given points: straight legs, by time or by speed"),
       [](const config::Settings& s, const MobilityContext& c) -> std::unique_ptr<MobilityModel> {
         return std::make_unique<WaypointModel>(waypoint_fields().build(s).model(), c.origin);
       }},
  };
  return all;
}

const MobilityComponent* find_mobility(std::string_view type) {
  const auto& all = mobility_components();
  const auto it = std::find_if(all.begin(), all.end(),
                               [type](const MobilityComponent& m) { return m.info.name == type; });
  return it == all.end() ? nullptr : &*it;
}

}  // namespace rfsitl::position::mobility
