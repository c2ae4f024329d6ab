#pragma once
/// What a mobility model registers: its self-description (name, doc, declared
/// settings) and how to build it for one node. The scenario selects one per
/// node (`mobility: {type: orbit, radius_m: 50}`); the engine evaluates it on
/// the virtual clock.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rfsitl/common/position.hpp"
#include "rfsitl/common/types.hpp"
#include "rfsitl/config/component_info.hpp"
#include "rfsitl/position/mobility/mobility_model.hpp"

namespace rfsitl::position::mobility {

/// What a model may take from the scenario besides its own settings.
struct MobilityContext {
  NodeId node = 1;
  std::uint64_t scenario_seed = 1;     ///< mixed with the node id where a model's seed is 0
  GeodeticPosition origin;             ///< where local x/y/z = 0
  std::optional<LocalPosition> start;  ///< the node's scenario position, if local
  std::string base_dir;                ///< relative file names are resolved here
  /// Told every problem that does not stop the model (a trace's bad lines, as
  /// "file:line: reason"); may be empty.
  std::function<void(const std::string&)> warn;
};

struct MobilityComponent {
  config::ComponentInfo info;  ///< kind "mobility"
  /// Builds the model from settings that passed info.validate(). Throws
  /// std::invalid_argument or std::runtime_error (an unreadable file).
  std::function<std::unique_ptr<MobilityModel>(const config::Settings&, const MobilityContext&)>
      make;
};

// The models by name: rfsitl/registry/mobility_registry.hpp.

}  // namespace rfsitl::position::mobility
