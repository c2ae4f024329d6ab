#include "rfsitl/registry/plugin_loader.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <system_error>

#include "rfsitl/registry/plugin.hpp"

namespace rfsitl::registry {
namespace {

using AbiFn = const char* (*)();
using RegisterFn = void (*)();

PluginLoad load_one(const std::string& path) {
  PluginLoad r{path, false, ""};
  // RTLD_LOCAL: plugins do not see each other's symbols, only the program's.
  // Kept loaded for the process's life: its components' code lives there.
  void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* why = ::dlerror();
    r.error = std::string("cannot load: ") + (why != nullptr ? why : "unknown reason");
    return r;
  }
  const auto abi = reinterpret_cast<AbiFn>(::dlsym(handle, "rfsitl_plugin_abi"));
  const auto reg = reinterpret_cast<RegisterFn>(::dlsym(handle, "rfsitl_plugin_register"));
  if (abi == nullptr || reg == nullptr) {
    r.error = "not an rfsitl plugin (no rfsitl_plugin_abi/rfsitl_plugin_register: RFSITL_PLUGIN)";
    ::dlclose(handle);
    return r;
  }
  const char* theirs = abi();
  if (std::strcmp(theirs, program_abi_tag()) != 0) {
    r.error = std::string("built for '") + theirs + "', this program is '" + program_abi_tag() +
              "': rebuild the plugin against this rfsitl";
    ::dlclose(handle);
    return r;
  }
  try {
    reg();
    r.loaded = true;
  } catch (const std::exception& e) {
    r.error = std::string("its registration failed: ") + e.what();
  }
  return r;
}

}  // namespace

const char* program_abi_tag() {
  return RFSITL_PLUGIN_ABI_TAG;
}

std::vector<std::string> plugin_folders(const std::string& installed) {
  std::vector<std::string> out;
  if (const char* env = std::getenv("RFSITL_PLUGIN_PATH")) {
    const std::string path(env);
    for (std::size_t at = 0; at <= path.size();) {
      const std::size_t colon = std::min(path.find(':', at), path.size());
      if (colon > at) out.push_back(path.substr(at, colon - at));
      at = colon + 1;
    }
  }
  if (!installed.empty()) out.push_back(installed);
  return out;
}

std::vector<PluginLoad> load_plugins(const std::vector<std::string>& folders) {
  std::vector<PluginLoad> out;
  for (const std::string& folder : folders) {
    std::error_code ec;
    std::vector<std::string> files;
    for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
      if (entry.path().extension() == ".so") files.push_back(entry.path().string());
    }
    std::sort(files.begin(), files.end());
    for (const std::string& f : files) out.push_back(load_one(f));
  }
  return out;
}

}  // namespace rfsitl::registry
