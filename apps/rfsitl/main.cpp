/// rfsitl: software-in-the-loop RF channel emulator for UAV swarms.
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <cstring>
#include <iostream>
#include <string>

#include "commands.hpp"
#include "rfsitl/common/build_version.hpp"
#include "rfsitl/registry/plugin_loader.hpp"

int main(int argc, char** argv) {
  // spdlog's default logger is created here, before any thread starts. It is a
  // function-local static inside the library, whose guard ThreadSanitizer
  // cannot see: a thread meeting it after another thread created it would look
  // unordered after that creation (scripts/test_tsan.sh).
  spdlog::default_logger_raw();
  CLI::App app{
      "rfsitl: software-in-the-loop RF channel emulator for UAV swarms and other multi-robot "
      "systems"};
  app.require_subcommand(1);
  // Plugins first: --help, describe and a scenario see their components.
  for (const auto& p : rfsitl::registry::load_plugins(rfsitl::app::plugin_folders())) {
    if (!p.loaded) std::cerr << "rfsitl: plugin " << p.path << " skipped: " << p.error << "\n";
  }
  app.set_version_flag("--version", std::string("rfsitl ") + rfsitl::build_version());
  auto run = rfsitl::app::add_run_command(app);
  auto ping = rfsitl::app::add_ping_command(app);
  auto links = rfsitl::app::add_links_command(app);
  auto node = rfsitl::app::add_node_command(app);
  auto describe = rfsitl::app::add_describe_command(app);
  auto mavlink_send = rfsitl::app::add_mavlink_send_command(app);
  auto sweep = rfsitl::app::add_sweep_command(app, argc, argv);
  auto man = rfsitl::app::add_man_command(app);
  auto completion = rfsitl::app::add_completion_command(app);
  // CLI11 would call an unknown command a missing one ("A subcommand is required").
  if (argc > 1 && argv[1][0] != '-' &&
      app.get_subcommands([&](CLI::App* c) { return c->check_name(argv[1]); }).empty()) {
    std::cerr << "rfsitl: unknown command '" << argv[1]
              << "' (commands: run, sweep, ping, links, describe, node, mavlink-send; see rfsitl "
                 "--help)\n";
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ArgumentMismatch& e) {
    // CLI11 says "--speed: At Most 1 required but received 2" for a flag given
    // twice; say it as a user would.
    const std::string what = e.what();
    const auto at = what.find(": At Most 1 required but received ");
    if (at == std::string::npos) return app.exit(e);
    std::cerr << "rfsitl: " << what.substr(0, at) << " given "
              << what.substr(at + std::strlen(": At Most 1 required but received "))
              << " times; give it once\n";
    return e.get_exit_code();
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  if (app.got_subcommand("run")) return run();
  if (app.got_subcommand("ping")) return ping();
  if (app.got_subcommand("links")) return links();
  if (app.got_subcommand("node")) return node();
  if (app.got_subcommand("describe")) return describe();
  if (app.got_subcommand("mavlink-send")) return mavlink_send();
  if (app.got_subcommand("sweep")) return sweep();
  if (app.got_subcommand("man")) return man();
  if (app.got_subcommand("completion")) return completion();
  return 2;
}
