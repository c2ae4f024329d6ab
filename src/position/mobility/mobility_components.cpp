// The registered mobility models and their declared settings. Each model's own
// settings struct nests a box or optional parts; the flat structs here are what
// a scenario writes, one key per field.
#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "rfsitl/common/xoshiro256.hpp"
#include "rfsitl/config/fields.hpp"
#include "rfsitl/position/mobility/csv_trace.hpp"
#include "rfsitl/position/mobility/gauss_markov_model.hpp"
#include "rfsitl/position/mobility/mobility_component.hpp"
#include "rfsitl/position/mobility/ns2_trace.hpp"
#include "rfsitl/position/mobility/orbit_model.hpp"
#include "rfsitl/position/mobility/random_waypoint_model.hpp"
#include "rfsitl/position/mobility/trace_replay_model.hpp"

namespace rfsitl::position::mobility {
namespace {

// A model's validate() says "<model>.<field> must be ..."; as a SettingError it
// names the field, so that the scenario reader can point at its line.
template <typename Settings>
void checked(const Settings& s) {
  try {
    s.validate();
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    const auto dot = what.find('.');
    const auto space = what.find(' ', dot);
    if (dot == std::string::npos || space == std::string::npos)
      throw config::SettingError("", what);
    throw config::SettingError(what.substr(dot + 1, space - dot - 1), what.substr(space + 1));
  }
}

// Seed 0: each node its own track, from the scenario's seed and the node id.
std::uint64_t node_seed(std::uint64_t seed, const MobilityContext& c) {
  if (seed != 0) return seed;
  std::uint64_t state = c.scenario_seed + 0x9E3779B97F4A7C15ULL * c.node;
  return splitmix64(state);
}

constexpr config::Range kAnyMetres{-1e8, 1e8};

const config::Fields<OrbitSettings>& orbit_fields() {
  using S = OrbitSettings;
  static const auto f = config::Fields<S>()
                            .real("centre_x_m", &S::centre_x_m, "m", kAnyMetres, "centre, east")
                            .real("centre_y_m", &S::centre_y_m, "m", kAnyMetres, "centre, north")
                            .real("radius_m", &S::radius_m, "m", {0, 1e8, true}, "radius")
                            .real("speed_mps", &S::speed_mps, "m/s", {-1e4, 1e4},
                                  "ground speed; positive counter-clockwise seen from above")
                            .real("altitude_m", &S::altitude_m, "m", kAnyMetres, "local z")
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
      .real("x_min_m", m(&BoxFields::x_min_m), "m", kAnyMetres, "box: least east")
      .real("x_max_m", m(&BoxFields::x_max_m), "m", kAnyMetres, "box: most east")
      .real("y_min_m", m(&BoxFields::y_min_m), "m", kAnyMetres, "box: least north")
      .real("y_max_m", m(&BoxFields::y_max_m), "m", kAnyMetres, "box: most north")
      .real("z_min_m", m(&BoxFields::z_min_m), "m", kAnyMetres, "box: lowest")
      .real("z_max_m", m(&BoxFields::z_max_m), "m", kAnyMetres, "box: highest")
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
