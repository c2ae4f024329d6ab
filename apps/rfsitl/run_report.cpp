#include "run_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <variant>

#include "rfsitl/common/build_version.hpp"
#include "rfsitl/monitor/node_counter_report.hpp"
#include "rfsitl/monitor/stats_report.hpp"

namespace rfsitl::app {
namespace {

std::string format_position(const std::optional<Position>& p) {
  if (!p) return "unknown until its location feed reports";
  char buf[96];
  if (const auto* g = std::get_if<GeodeticPosition>(&*p)) {
    std::snprintf(buf, sizeof buf, "lat %.6f lon %.6f alt %.1f m", g->lat_deg, g->lon_deg,
                  g->alt_m);
  } else {
    const auto& l = std::get<LocalPosition>(*p);
    std::snprintf(buf, sizeof buf, "x %.1f y %.1f z %.1f m", l.x_m, l.y_m, l.z_m);
  }
  return buf;
}

}  // namespace

void print_banner(const scenario::Scenario& s, const agent_port::NetPortsConfig& sc,
                  const LiveSources& sources, const engine::Engine& engine,
                  const std::vector<std::string>& served_by) {
  const double tick_ms = 1e3 * s.timing.tick_samples / s.timing.sample_rate_hz;
  std::printf(
      "rfsitl: scenario '%s': %zu nodes, fs %.0f Hz, tick %u samples (%.3f ms), %s x%.2f, "
      "noise %.1f dB, seed %llu\n",
      s.name.c_str(), s.nodes.size(), s.timing.sample_rate_hz, s.timing.tick_samples, tick_ms,
      s.timing.mode == scenario::TimeMode::kRealTime ? "real time" : "virtual time", s.timing.speed,
      10.0 * std::log10(s.channel.noise_variance), static_cast<unsigned long long>(s.seed));
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    const auto& n = s.nodes[i];
    const bool own_net = !s.phy_of(i).external_program();
    std::string where = n.mobility ? "moves: mobility " + n.mobility->type
                                   : "start " + format_position(n.initial_position);
    if (const auto live = sources.status(i);
        live && live->type != "mobility" && live->type != "location_port") {
      where += ", follows " + live->type + " " + live->where;
    }
    const unsigned net_port = agent_port::NetPorts::net_port(sc, n.id);
    if (i < served_by.size() && !served_by[i].empty()) {
      // Its ports are on that rank's host, at the same port numbers.
      std::printf("  node %3u: %-26s net %u%s  location %u  on %s  %s\n", n.id,
                  s.phy_of(i).label().c_str(), net_port, own_net ? "" : " (its program's)",
                  unsigned{s.ports.loc_base} + 10U * n.id, served_by[i].c_str(), where.c_str());
      continue;
    }
    std::printf("  node %3u: %-26s net %s:%u%s  location %s  %s\n", n.id,
                s.phy_of(i).label().c_str(), sc.bind_address.c_str(), net_port,
                own_net ? "" : " (its program's)", sources.location_port(i).c_str(), where.c_str());
  }
  if (s.mac.type != "none") std::printf("rfsitl: mac %s\n", engine.mac_description(0).c_str());
}

void print_stats_line(engine::Engine& e) {
  const engine::EngineStatus st = e.status();
  engine::NodeCountersSnapshot total;
  for (std::size_t i = 0; i < e.num_nodes(); ++i) {
    const auto c = e.counters(i).snapshot();
    total.handed_in += c.handed_in;
    total.delivered += c.delivered;
    total.queue_dropped += c.queue_dropped;
    for (std::size_t r = 0; r < engine::kNumLossReasons; ++r) total.lost[r] += c.lost[r];
  }
  std::printf(
      "[stats] virtual %.1f s, wall %.1f s, lag %.2f ms (max %.2f ms), frames in %llu, "
      "delivered %llu, lost %llu, queue-dropped %llu, pending %llu\n",
      st.virtual_s, st.wall_s, 1e3 * st.lag_s, 1e3 * st.max_lag_s,
      static_cast<unsigned long long>(total.handed_in),
      static_cast<unsigned long long>(total.delivered),
      static_cast<unsigned long long>(total.lost_total()),
      static_cast<unsigned long long>(total.queue_dropped),
      static_cast<unsigned long long>(total.pending()));
  std::fflush(stdout);
}

void print_summary(engine::Engine& e) {
  const engine::EngineStatus st = e.status();
  std::printf(
      "\nrfsitl summary: virtual %.3f s in %.3f s wall, worst real-time lag %.2f ms, "
      "late ticks %llu\n",
      st.virtual_s, st.wall_s, 1e3 * st.max_lag_s, static_cast<unsigned long long>(st.late_ticks));
  const auto counters = monitor::all_node_counters(e);
  std::fputs(monitor::node_counters_table(e.node_ids(), counters).c_str(), stdout);
  std::fputs(monitor::node_counters_legend(counters).c_str(), stdout);
  std::fflush(stdout);
}

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

void print_external_summary(const nlohmann::json& j) {
  std::string where = j["socket"].is_string() ? j["socket"].get<std::string>() : "";
  if (j.contains("sockets")) {
    where.clear();
    for (const auto& socket : j["sockets"]) {
      if (socket.is_string()) where += (where.empty() ? "" : ", ") + socket.get<std::string>();
    }
  }
  std::printf("external transceivers (%s): %llu connection(s) refused, %llu child restart(s)\n",
              where.c_str(),
              static_cast<unsigned long long>(j["rejected_connections"].get<std::uint64_t>()),
              static_cast<unsigned long long>(j["child_restarts"].get<std::uint64_t>()));
  for (const auto& n : j["nodes"]) {
    std::printf("  node %3u %-11s joins %llu, drops %llu, timeouts %llu\n", n["id"].get<unsigned>(),
                n["role"].get<std::string>().c_str(),
                static_cast<unsigned long long>(n["joins"].get<std::uint64_t>()),
                static_cast<unsigned long long>(n["drops"].get<std::uint64_t>()),
                static_cast<unsigned long long>(n["timeouts"].get<std::uint64_t>()));
  }
  std::fflush(stdout);
}

void print_ip_banner(const std::vector<agent_port::IpNodeInfo>& nodes) {
  for (const auto& n : nodes) {
    std::printf("  node %3u: netns %s%s  %s %s  %s  %s  MTU %zu\n", n.id, n.netns.c_str(),
                n.netns_owned ? "" : " (attached)", n.interface.c_str(), n.mac.c_str(),
                n.ipv4.c_str(), n.ipv6.c_str(), n.mtu);
  }
  if (nodes.size() >= 2) {
    const std::string to = nodes[1].ipv4.substr(0, nodes[1].ipv4.find('/'));
    std::printf("rfsitl: IP on every node; e.g. ip netns exec %s ping %s\n", nodes[0].netns.c_str(),
                to.c_str());
  }
  std::fflush(stdout);
}

void print_partial_summary(engine::Engine& e, const RunRanks& ranks) {
  std::vector<NodeId> ids;
  std::vector<engine::NodeCountersSnapshot> counters;
  for (std::size_t i = 0; i < e.num_nodes(); ++i) {
    if (!ranks.here(i)) continue;
    ids.push_back(e.node_ids()[i]);
    counters.push_back(e.counters(i).snapshot());
  }
  std::printf(
      "\nrfsitl: rank %zu of %zu: the other ranks stopped answering (one of them failed?); the "
      "counters of this rank's nodes at virtual %.3f s:\n%s",
      ranks.rank, ranks.size, e.status().virtual_s,
      monitor::node_counters_table(ids, counters).c_str());
  std::fflush(stdout);
}

nlohmann::json summary_json(const RunSummaryParts& p) {
  nlohmann::json j = monitor::stats_with_links_json(p.scenario, p.engine, p.sources.status_fn());
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

}  // namespace rfsitl::app
