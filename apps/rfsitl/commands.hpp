#pragma once
/// Sub-commands of the `rfsitl` executable.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

namespace rfsitl::app {

/// Registers `rfsitl run` on `parent`; the returned action runs it (exit code).
std::function<int()> add_run_command(CLI::App& parent);

/// Registers `rfsitl ping` on `parent`.
std::function<int()> add_ping_command(CLI::App& parent);

/// Registers `rfsitl links`: a running emulator's live link table.
std::function<int()> add_links_command(CLI::App& parent);

/// Registers `rfsitl describe`: the registered components and their settings.
std::function<int()> add_describe_command(CLI::App& parent);

/// Registers `rfsitl node`: one node's transceiver in its own process.
std::function<int()> add_node_command(CLI::App& parent);

/// Where this program loads plugins from: RFSITL_PLUGIN_PATH, then the plugin
/// folder of the prefix the executable is installed in (when it is).
std::vector<std::string> plugin_folders();

/// Registers `rfsitl mavlink-send`: stand-in MAVLink vehicles for --mavlink.
std::function<int()> add_mavlink_send_command(CLI::App& parent);

}  // namespace rfsitl::app
