// Where `rfsitl` finds what is installed beside it (plugins, scenarios):
// relative to the executable, so that an installed tree can move to another
// prefix and still find them.
#include <filesystem>
#include <system_error>

#include "commands.hpp"
#include "rfsitl/registry/plugin_loader.hpp"

namespace rfsitl::app {
namespace {

/// <prefix>/`subdir` when this executable is <prefix>/bin/rfsitl; empty for a
/// build tree's executable (not in a bin folder).
std::filesystem::path installed(const char* subdir) {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec || exe.parent_path().filename() != std::filesystem::path(RFSITL_BIN_SUBDIR).filename()) {
    return {};
  }
  return exe.parent_path().parent_path() / subdir;
}

}  // namespace

std::vector<std::string> plugin_folders() {
  const std::filesystem::path dir = installed(RFSITL_PLUGIN_SUBDIR);
  return registry::plugin_folders(dir.empty() ? std::string() : dir.string());
}

std::string scenario_file(const std::string& path) {
  std::error_code ec;
  if (path.empty() || path.find('/') != std::string::npos || std::filesystem::exists(path, ec)) {
    return path;
  }
  const std::filesystem::path dir = installed(RFSITL_DATA_SUBDIR);
  if (dir.empty()) return path;
  const std::filesystem::path bundled = dir / "scenarios" / path;
  return std::filesystem::exists(bundled, ec) ? bundled.string() : path;
}

}  // namespace rfsitl::app
