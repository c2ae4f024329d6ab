#pragma once
/// Settings as JSON, e.g. how the emulator tells an `rfsitl node` process which
/// transceiver to build.
#include <nlohmann/json.hpp>

#include "rfsitl/config/component_info.hpp"

namespace rfsitl::config {

/// A value as JSON: a boolean, number or string; a list setting's records as
/// an array of objects.
nlohmann::json to_json(const Value& value);

/// {"kind", "name", "doc", "settings": [{"name", "type", "default", "unit",
/// "limits", "choices", "doc"}, ...]}: what `rfsitl describe` prints, as data
/// (`rfsitl describe --json`, the Python module's rfsitl.components()).
nlohmann::json component_json(const ComponentInfo& component);

/// {"name": value, ...} in declaration order; a list setting is an array of
/// objects, [{"t": 0, "x": 1}, ...].
nlohmann::json to_json(const Settings& s);

/// Reads `j` (an object) as settings of `component`: every declared key must be
/// present and of its type (an integer is accepted for a real), no other key may
/// be, and the values are validated. Throws SettingError, whose key names a
/// list's item and field ("points[1].t") when the fault is there.
Settings settings_from_json(const ComponentInfo& component, const nlohmann::json& j);

}  // namespace rfsitl::config
