#pragma once
// Internal to the mobility model folders: what their declared settings share.
// Each model's own settings struct nests a box or optional parts; the flat
// structs of the folders are what a scenario writes, one key per field.
#include <cstdint>
#include <stdexcept>
#include <string>

#include "rfsitl/common/position_limits.hpp"
#include "rfsitl/common/xoshiro256.hpp"
#include "rfsitl/config/fields.hpp"
#include "rfsitl/position/mobility/mobility_component.hpp"

namespace rfsitl::position::mobility::detail {

// A model says "<model>.<field> must be ..." (or "<model>.<field>: why"); as a
// SettingError it names the field, so that the scenario reader can point at its line.
inline config::SettingError setting_error(const std::invalid_argument& e) {
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
inline std::uint64_t node_seed(std::uint64_t seed, const MobilityContext& c) {
  if (seed != 0) return seed;
  std::uint64_t state = c.scenario_seed + 0x9E3779B97F4A7C15ULL * c.node;
  return splitmix64(state);
}

// The limits every input of positions accepts (common/position_limits.hpp).
constexpr config::Range kEastNorth{kHorizontalLimit.lo, kHorizontalLimit.hi};
constexpr config::Range kHeight{kAltitudeLimit.lo, kAltitudeLimit.hi};

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

}  // namespace rfsitl::position::mobility::detail
