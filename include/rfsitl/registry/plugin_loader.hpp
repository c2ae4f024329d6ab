#pragma once
/// Loads plugins (plugin.hpp) from folders, as SoapySDR loads its modules.
#include <string>
#include <vector>

namespace rfsitl::registry {

/// What became of one plugin file.
struct PluginLoad {
  std::string path;
  bool loaded = false;  ///< its components are registered
  std::string error;    ///< why not (when !loaded): unloadable, no entry points,
                        ///< another ABI, or its registration threw
};

/// The folders plugins are loaded from, in order: each of RFSITL_PLUGIN_PATH
/// (colon-separated; empty entries skipped), then `installed` (the plugin
/// folder of an installed rfsitl; skipped when empty).
std::vector<std::string> plugin_folders(const std::string& installed);

/// Loads every `*.so` of each folder (a folder that does not exist is
/// skipped), in name order within a folder. Call once at start, on one thread,
/// before any component is used by a run (registry.hpp). A plugin is
/// registered only when its ABI tag equals this program's; its registration
/// may still fail part-way (a name already taken), which its PluginLoad says.
/// Never throws for a bad plugin.
std::vector<PluginLoad> load_plugins(const std::vector<std::string>& folders);

/// This program's ABI tag (RFSITL_PLUGIN_ABI_TAG as it was built).
const char* program_abi_tag();

}  // namespace rfsitl::registry
