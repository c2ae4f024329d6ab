#pragma once
/// What `rfsitl run` prints and writes about a run: the banner, the periodic
/// stats line, the per-node summary and the summary JSON. Rank 0 speaks for
/// a distributed run; these functions only format.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "distributed_run.hpp"
#include "live_sources.hpp"
#include "rfsitl/agent_port/ip_ports.hpp"
#include "rfsitl/agent_port/net_ports.hpp"
#include "rfsitl/engine/engine.hpp"
#include "rfsitl/monitor/pcap_trace.hpp"
#include "rfsitl/monitor/sigmf_recorder.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::app {

/// The scenario's line and one line per node: transceiver, ports, where it is.
/// `served_by`: for each node another rank serves, that rank ("rank 1 on
/// host-b"), whose host its ports are on; empty for this process's nodes (or
/// an empty vector in a run of one process).
void print_banner(const scenario::Scenario& s, const agent_port::NetPortsConfig& ports,
                  const LiveSources& sources, const engine::Engine& engine,
                  const std::vector<std::string>& served_by);

/// Each node's namespace, interface and addresses, and a ping to try.
void print_ip_banner(const std::vector<agent_port::IpNodeInfo>& nodes);

/// "[stats] ..." : the clock, the lag and every node's frames summed.
void print_stats_line(engine::Engine& e);

/// The closing clock line and the per-node counters table.
void print_summary(engine::Engine& e);

/// A rank whose peers stopped answering: the counters of its own nodes so
/// far, for the user to put together.
void print_partial_summary(engine::Engine& e, const RunRanks& ranks);

/// Every rank's ExternalRuntime::summary() (texts, in rank order) as one: the
/// nodes of all (in scenario order), the counts summed; in a distributed run
/// also "sockets", each rank's (null for a rank that serves none).
nlohmann::json merge_external_summaries(const std::vector<std::string>& texts,
                                        const engine::Engine& engine);

/// One line per external node: how often its process joined, was dropped and
/// timed out, so that a flaky flowgraph shows at a glance.
void print_external_summary(const nlohmann::json& j);

/// What the summary JSON is made of; absent parts are null.
struct RunSummaryParts {
  const scenario::Scenario& scenario;
  engine::Engine& engine;
  const LiveSources& sources;
  const RunRanks& ranks;
  const nlohmann::json* external = nullptr;  ///< merge_external_summaries()
  const monitor::PcapTrace* pcap = nullptr;
  const monitor::SigmfRecorder* sigmf = nullptr;
  const agent_port::IpPorts* ip = nullptr;
  const std::vector<agent_port::IpNodeInfo>& ip_nodes;  ///< every rank's interfaces
  const nlohmann::json& ip_stale;                       ///< every rank's removed namespaces
};

/// `--summary-json`: the dashboard's stats with links, and the run's parts
/// (external nodes, traces, IP, MAC, the ranks of a distributed run).
nlohmann::json summary_json(const RunSummaryParts& parts);

}  // namespace rfsitl::app
