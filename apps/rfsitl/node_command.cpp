/// `rfsitl node`: runs one node's built-in transceiver in its own process, in
/// lock-step with an emulator whose scenario declares the node `process: child`
/// (the emulator normally starts these itself; by hand it is for debugging).
#include <signal.h>
#include <sys/prctl.h>

#include <atomic>
#include <cstdio>
#include <stdexcept>

#include "commands.hpp"
#include "rfsitl/external/transceiver_node.hpp"

namespace rfsitl::app {
namespace {

std::atomic<bool> g_stop{false};

struct NodeOptions {
  external::TransceiverNodeOptions node;
  unsigned id = 0;
  bool exit_with_parent = false;
};

int run_node(NodeOptions& o) {
  if (o.exit_with_parent) prctl(PR_SET_PDEATHSIG, SIGTERM);
  struct sigaction sa {};
  sa.sa_handler = [](int) { g_stop.store(true); };
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  o.node.node_id = static_cast<NodeId>(o.id);
  try {
    return external::run_transceiver_node(o.node, g_stop);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rfsitl node %u: %s\n", o.id, e.what());
    return 1;
  }
}

}  // namespace

std::function<int()> add_node_command(CLI::App& parent) {
  auto opts = std::make_shared<NodeOptions>();
  CLI::App* cmd = parent.add_subcommand(
      "node",
      "One node's transceiver in its own process. Started by `rfsitl run` itself for nodes with "
      "phy.process: child (or --arch split); not meant to be run by hand");
  cmd->add_option("--socket", opts->node.socket_path, "The emulator's external socket")
      ->type_name("PATH")
      ->required();
  cmd->add_option("--id", opts->id, "Node id")->required()->check(CLI::Range(1, int{kMaxNodeId}));
  cmd->add_option("--connect-timeout", opts->node.connect_timeout_s,
                  "Seconds to keep trying to join (the pause between attempts doubles from "
                  "50 ms to 2 s; a refusal's reason is printed once)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--exit-with-parent", opts->exit_with_parent,
                "End when the process that started this one ends");
  return [opts] { return run_node(*opts); };
}

}  // namespace rfsitl::app
