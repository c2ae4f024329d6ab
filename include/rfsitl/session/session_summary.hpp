#pragma once
/// What a run leaves behind: its clock, every node's counters, and the parts'
/// own summaries, as Session::finish() gathers them and `--summary-json`
/// writes them. Formatting for a terminal is the caller's (apps/rfsitl).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rfsitl/agent_port/ip_ports.hpp"
#include "rfsitl/engine/engine.hpp"
#include "rfsitl/monitor/pcap_trace.hpp"
#include "rfsitl/monitor/sigmf_recorder.hpp"
#include "rfsitl/scenario/scenario.hpp"
#include "rfsitl/session/live_sources.hpp"
#include "rfsitl/session/run_ranks.hpp"

namespace rfsitl::session {

/// The run at its end. In a distributed run every rank holds the same counters
/// (every rank's nodes: the engine gathers them at the end); `document` is
/// meant to be written by rank 0.
struct SessionSummary {
  engine::EngineStatus status;   ///< the clock at the end (virtual and wall seconds, lag)
  std::vector<NodeId> node_ids;  ///< in index order
  /// By node index; queue_depth is the TX queue's length at the end.
  std::vector<engine::NodeCountersSnapshot> counters;
  nlohmann::json external;  ///< merge_external_summaries(); null without external nodes
  nlohmann::json pcap;      ///< monitor::PcapTrace::summary(); null without a trace
  nlohmann::json sigmf;     ///< monitor::SigmfRecorder::summary(); null without a recording
  nlohmann::json document;  ///< summary_json(): what --summary-json writes
};

/// Every rank's external::ExternalRuntime::summary() (texts, in rank order) as
/// one: the nodes of all (in scenario order), the counts summed; in a
/// distributed run also "sockets", each rank's (null for a rank that serves
/// none). Precondition: texts is not empty.
nlohmann::json merge_external_summaries(const std::vector<std::string>& texts,
                                        const engine::Engine& engine);

/// What the summary JSON is made of; absent parts are null.
struct RunSummaryParts {
  const scenario::Scenario& scenario;
  engine::Engine& engine;
  const LiveSources* sources = nullptr;  ///< null: a run without ports
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
/// Reads the engine's thread-safe views; call after its run.
nlohmann::json summary_json(const RunSummaryParts& parts);

}  // namespace rfsitl::session
