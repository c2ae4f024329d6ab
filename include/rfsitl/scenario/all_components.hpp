#pragma once
/// Every registered component of every kind and the scenario's own sections
/// that declare settings (the radio, the spectrum), as `rfsitl describe`, the
/// manual pages and the Python module list them.
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "rfsitl/config/component_info.hpp"

namespace rfsitl::scenario {

/// Grouped by kind in data-path order: where nodes are (live sources,
/// mobility models), the transceivers, their MACs, the channel's stages (on
/// links, then on samples), the radio whose link budget they complete, and
/// the spectrum's sections (spectrum, a channel plan, a node's tuning).
/// Plugins loaded so far included. Pointers stay valid (registry.hpp).
std::vector<const config::ComponentInfo*> all_components();

/// Those of kind `kind` ("": all) as a JSON array of config::component_json():
/// `rfsitl describe --json` and rfsitl.components() in Python.
nlohmann::json all_components_json(std::string_view kind = {});

}  // namespace rfsitl::scenario
