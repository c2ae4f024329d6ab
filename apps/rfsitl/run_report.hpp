#pragma once
/// What `rfsitl run` prints about a run: the banner, the periodic stats line,
/// the per-node summary. Rank 0 speaks for a distributed run; these functions
/// only format (the summary JSON is the session's: session/session_summary.hpp).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rfsitl/agent_port/ip_ports.hpp"
#include "rfsitl/agent_port/net_ports.hpp"
#include "rfsitl/engine/engine.hpp"
#include "rfsitl/scenario/scenario.hpp"
#include "rfsitl/session/live_sources.hpp"
#include "rfsitl/session/run_ranks.hpp"

namespace rfsitl::app {

/// The scenario's line and one line per node: transceiver, ports, where it is.
/// `served_by`: for each node another rank serves, that rank ("rank 1 on
/// host-b"), whose host its ports are on; empty for this process's nodes (or
/// an empty vector in a run of one process).
void print_banner(const scenario::Scenario& s, const agent_port::NetPortsConfig& ports,
                  const session::LiveSources& sources, const engine::Engine& engine,
                  const std::vector<std::string>& served_by);

/// Each node's namespace, interface and addresses, and a ping to try.
void print_ip_banner(const std::vector<agent_port::IpNodeInfo>& nodes);

/// "[stats] ..." : the clock, the lag and every node's frames summed.
void print_stats_line(engine::Engine& e);

/// The closing clock line and the per-node counters table.
void print_summary(engine::Engine& e);

/// A rank whose peers stopped answering: the counters of its own nodes so
/// far, for the user to put together.
void print_partial_summary(engine::Engine& e, const session::RunRanks& ranks);

/// One line per external node: how often its process joined, was dropped and
/// timed out, so that a flaky flowgraph shows at a glance.
void print_external_summary(const nlohmann::json& j);

}  // namespace rfsitl::app
