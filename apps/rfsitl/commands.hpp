#pragma once
/// Sub-commands of the `rfsitl` executable.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

#include "rfsitl/config/component_info.hpp"

namespace rfsitl::app {

/// Registers `rfsitl run` on `parent`; the returned action runs it (exit code).
std::function<int()> add_run_command(CLI::App& parent);

/// Registers `rfsitl ping` on `parent`.
std::function<int()> add_ping_command(CLI::App& parent);

/// Registers `rfsitl links`: a running emulator's live link table.
std::function<int()> add_links_command(CLI::App& parent);

/// Registers `rfsitl describe`: the registered components and their settings.
std::function<int()> add_describe_command(CLI::App& parent);

/// Registers the hidden `rfsitl man [COMMAND] [--directory DIR]`: the manual
/// pages (roff) of the program, of each command and of the components
/// (rfsitl-components(7)), from the same declarations --help and describe use.
std::function<int()> add_man_command(CLI::App& parent);

/// Registers the hidden `rfsitl completion bash`: the bash completion script.
std::function<int()> add_completion_command(CLI::App& parent);

/// Registers `rfsitl node`: one node's transceiver in its own process.
std::function<int()> add_node_command(CLI::App& parent);

/// Where this program loads plugins from: RFSITL_PLUGIN_PATH, then the plugin
/// folder of the prefix the executable is installed in (when it is).
std::vector<std::string> plugin_folders();

/// `path` itself, unless it is a bare file name that does not exist here but
/// is one of the scenarios installed with this program
/// (<prefix>/share/rfsitl/scenarios): then that file's path.
std::string scenario_file(const std::string& path);

/// Registers `rfsitl sweep`: a campaign of runs (rfsitl/campaign/). `argc` and
/// `argv` are the program's, for the manifest.
std::function<int()> add_sweep_command(CLI::App& parent, int argc, char** argv);

/// Registers `rfsitl mavlink-send`: stand-in MAVLink vehicles for --mavlink.
std::function<int()> add_mavlink_send_command(CLI::App& parent);

}  // namespace rfsitl::app
