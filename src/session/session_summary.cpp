#include "rfsitl/session/session_summary.hpp"

#include <algorithm>

#include "rfsitl/common/build_version.hpp"
#include "rfsitl/monitor/stats_report.hpp"

namespace rfsitl::session {

nlohmann::json merge_external_summaries(const std::vector<std::string>& texts,
                                        const engine::Engine& engine) {
  nlohmann::json merged = nlohmann::json::parse(texts.at(0));
  if (texts.size() == 1) return merged;
  nlohmann::json sockets = nlohmann::json::array({merged["socket"]});
  for (std::size_t r = 1; r < texts.size(); ++r) {
    const nlohmann::json j = nlohmann::json::parse(texts[r]);
    sockets.push_back(j["socket"]);
    for (const char* key : {"rejected_connections", "child_restarts"}) {
      merged[key] = merged[key].get<std::uint64_t>() + j[key].get<std::uint64_t>();
    }
    for (const auto& n : j["nodes"]) merged["nodes"].push_back(n);
  }
  std::sort(merged["nodes"].begin(), merged["nodes"].end(), [&](const auto& a, const auto& b) {
    return engine.index_of(a["id"].template get<NodeId>()) <
           engine.index_of(b["id"].template get<NodeId>());
  });
  merged["sockets"] = sockets;
  return merged;
}

nlohmann::json summary_json(const RunSummaryParts& p) {
  nlohmann::json j = monitor::stats_with_links_json(
      p.scenario, p.engine, p.sources ? p.sources->status_fn() : position::SourceStatusFn{});
  j["rfsitl_version"] = build_version();
  if (p.external) j["external"] = *p.external;
  if (p.pcap) j["pcap"] = p.pcap->summary();
  if (p.sigmf) j["sigmf"] = p.sigmf->summary();
  if (p.ip) {
    j["ip"] = p.ip->summary();
    if (p.ranks.distributed()) {
      // Every rank's interfaces; the frame counts were this rank's alone
      // (the nodes' own counters hold every rank's).
      j["ip"]["nodes"] = nlohmann::json::array();
      for (const auto& n : p.ip_nodes) j["ip"]["nodes"].push_back(agent_port::ip_node_json(n));
      j["ip"]["removed_stale"] = p.ip_stale;
      j["ip"].erase("frames_to_tap");
      j["ip"].erase("frames_from_tap");
    }
  }
  j["mac"] = {{"type", p.scenario.mac.type}, {"description", p.engine.mac_description(0)}};
  if (p.ranks.distributed()) {
    nlohmann::json per_rank = nlohmann::json::array();
    const auto rank_figures = p.engine.ranks();
    for (std::size_t r = 0; r < rank_figures.size(); ++r) {
      const engine::RankStatus& f = rank_figures[r];
      per_rank.push_back({{"host", r < p.ranks.hosts.size() ? p.ranks.hosts[r] : std::string()},
                          {"max_lag_s", f.max_lag_s},
                          {"late_ticks", f.late_ticks},
                          {"exchanged_bytes", f.exchanged_bytes},
                          {"exchange_wall_s", f.exchange_wall_s},
                          {"wall_s", f.wall_s}});
    }
    j["distributed"] = {
        {"ranks", p.ranks.size}, {"owner_rank", p.ranks.owner}, {"per_rank", per_rank}};
  }
  return j;
}

}  // namespace rfsitl::session
