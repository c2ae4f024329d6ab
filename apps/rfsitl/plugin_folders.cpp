// Where `rfsitl` loads plugins from: relative to the executable, so that an
// installed tree can move to another prefix and still find its plugins.
#include <filesystem>
#include <system_error>

#include "commands.hpp"
#include "rfsitl/registry/plugin_loader.hpp"

namespace rfsitl::app {

std::vector<std::string> plugin_folders() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  std::string installed;
  // <prefix>/bin/rfsitl -> <prefix>/lib/<arch>/rfsitl/plugins; a build tree's
  // executable (not in a bin folder) has none.
  if (!ec && exe.parent_path().filename() == std::filesystem::path(RFSITL_BIN_SUBDIR).filename()) {
    installed = (exe.parent_path().parent_path() / RFSITL_PLUGIN_SUBDIR).string();
  }
  return registry::plugin_folders(installed);
}

}  // namespace rfsitl::app
