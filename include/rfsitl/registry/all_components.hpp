#pragma once
/// Every registered component of every kind, as `rfsitl describe`, the manual
/// pages and the Python module list them.
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "rfsitl/config/component_info.hpp"

namespace rfsitl::registry {

/// Grouped by kind in data-path order: where nodes are (live sources,
/// mobility models), the transceivers, their MACs, the channel's stages (on
/// links, then on samples), and the radio whose link budget they complete.
/// Plugins loaded so far included. Pointers stay valid (registry.hpp).
std::vector<const config::ComponentInfo*> all_components();

/// Those of kind `kind` ("": all) as a JSON array of config::component_json():
/// `rfsitl describe --json` and rfsitl.components() in Python.
nlohmann::json all_components_json(std::string_view kind = {});

}  // namespace rfsitl::registry
