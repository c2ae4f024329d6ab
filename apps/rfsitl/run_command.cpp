/// `rfsitl run`: load a scenario, open the ports, run the engine until a signal
/// or the scenario's duration, then print the per-node summary.
#include <pthread.h>
#include <signal.h>

#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "rfsitl/engine/engine.hpp"
#include "rfsitl/external/external_runtime.hpp"
#include "rfsitl/io/node_servers.hpp"
#include "rfsitl/monitor/dashboard.hpp"
#include "rfsitl/monitor/pcap_trace.hpp"
#include "rfsitl/monitor/sigmf_recorder.hpp"
#include "rfsitl/monitor/stats_report.hpp"
#include "rfsitl/scenario/default_formation.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"

namespace rfsitl::app {
namespace {

struct RunOptions {
  std::string scenario_path;
  std::optional<std::size_t> nodes;
  std::optional<std::uint16_t> net_base;
  std::optional<std::uint16_t> loc_base;
  std::optional<std::string> bind;
  std::optional<std::string> mode;
  std::optional<double> speed;
  std::optional<double> duration_s;
  std::optional<double> sample_rate_hz;
  std::optional<std::uint32_t> tick_samples;
  std::optional<std::uint64_t> seed;
  std::optional<unsigned> threads;
  std::optional<double> noise_db;
  std::optional<double> stats_interval_s;
  std::optional<std::string> arch;
  std::optional<std::string> phy_type;
  std::optional<std::string> external_socket;
  std::optional<double> external_timeout_s;
  std::string pcap_path;
  double pcap_max_mb = 100.0;
  unsigned pcap_files = 5;
  std::string sigmf_dir;
  std::vector<unsigned> sigmf_nodes;
  double sigmf_start_s = 0.0;
  double sigmf_duration_s = 10.0;
  double sigmf_max_mb = 200.0;
  std::optional<std::uint16_t> dashboard_port;
  bool no_dashboard = false;
  bool dashboard_control = false;
  bool no_skip = false;
  bool shared_noise = false;
  std::string summary_json;
};

scenario::Scenario build_scenario(const RunOptions& o) {
  scenario::Scenario s;
  if (!o.scenario_path.empty()) s = scenario::load_scenario_file(o.scenario_path);
  if (o.net_base) s.ports.net_base = *o.net_base;
  if (o.loc_base) s.ports.loc_base = *o.loc_base;
  if (o.bind) s.ports.bind_address = *o.bind;
  if (o.mode) {
    s.timing.mode =
        *o.mode == "virtual" ? scenario::TimeMode::kVirtual : scenario::TimeMode::kRealTime;
  }
  if (o.speed) s.timing.speed = *o.speed;
  if (o.duration_s) s.timing.duration_s = *o.duration_s;
  if (o.sample_rate_hz) s.timing.sample_rate_hz = *o.sample_rate_hz;
  if (o.tick_samples) s.timing.tick_samples = *o.tick_samples;
  if (o.seed) s.seed = *o.seed;
  if (o.threads) s.engine.threads = *o.threads;
  if (o.noise_db) s.channel.noise_variance = std::pow(10.0, *o.noise_db / 10.0);
  if (o.stats_interval_s) s.engine.stats_interval_s = *o.stats_interval_s;
  if (o.no_skip) s.engine.skip_idle_receivers = false;
  if (o.shared_noise) s.channel.shared_noise = true;
  if (o.nodes || s.nodes.empty()) {
    s.nodes = scenario::default_formation(o.nodes.value_or(6), s.channel);
    s.traffic.clear();  // it named the file's nodes
    if (o.scenario_path.empty()) s.name = "default-formation";
  }
  if (o.phy_type) s.phy.type = *o.phy_type;  // nodes without a phy of their own
  if (o.arch) {
    // Every built-in transceiver moves: threads = in the emulator, split = one
    // `rfsitl node` process each. External programs stay what they are.
    const std::string process = *o.arch == "split" ? "child" : "inline";
    s.phy.process = process;
    for (auto& n : s.nodes) {
      if (n.phy) n.phy->process = process;
    }
  }
  if (o.external_socket) s.external.socket_path = *o.external_socket;
  if (o.external_timeout_s) s.external.reply_timeout_s = *o.external_timeout_s;
  scenario::validate_scenario(s);
  return s;
}

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

std::string describe_phy(const scenario::PhyConfig& p) {
  if (p.type == "external") return "external program";
  if (p.process == "child") {
    scenario::PhyConfig inline_phy = p;
    inline_phy.process = "inline";
    return describe_phy(inline_phy) + " [child]";
  }
  if (p.type == "ofdm") return "ofdm " + std::to_string(p.rate_mbps) + " Mbit/s";
  if (p.type == "dsss") return "dsss " + p.code + " " + p.modulation;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s k=%u BT=%.2f", p.type.c_str(), p.samples_per_symbol,
                static_cast<double>(p.bandwidth_time));
  return buf;
}

void print_banner(const scenario::Scenario& s, const io::ServerConfig& sc) {
  const double tick_ms = 1e3 * s.timing.tick_samples / s.timing.sample_rate_hz;
  std::printf(
      "rfsitl: scenario '%s': %zu nodes, fs %.0f Hz, tick %u samples (%.3f ms), %s x%.2f, "
      "noise %.1f dB, seed %llu\n",
      s.name.c_str(), s.nodes.size(), s.timing.sample_rate_hz, s.timing.tick_samples, tick_ms,
      s.timing.mode == scenario::TimeMode::kRealTime ? "real time" : "virtual time", s.timing.speed,
      10.0 * std::log10(s.channel.noise_variance), static_cast<unsigned long long>(s.seed));
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    const auto& n = s.nodes[i];
    const bool own_net = s.phy_of(i).type != "external";
    std::printf("  node %3u: %-26s net %s:%u%s  location %s:%u  start %s\n", n.id,
                describe_phy(s.phy_of(i)).c_str(), sc.bind_address.c_str(),
                io::NodeServers::net_port(sc, n.id), own_net ? "" : " (its program's)",
                sc.bind_address.c_str(), io::NodeServers::loc_port(sc, n.id),
                format_position(n.initial_position).c_str());
  }
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
  std::printf("%5s %8s %8s %9s %8s %8s %8s %8s %8s %8s %8s %8s %8s %7s %7s\n", "node", "in", "tx",
              "delivered", "lost:sen", "lost:col", "lost:hd", "lost:dec", "lost:dst", "q-drop",
              "pending", "received", "crc-fail", "loc-ok", "loc-bad");
  for (std::size_t i = 0; i < e.num_nodes(); ++i) {
    const auto c = e.counters(i).snapshot();
    const auto u = [](std::uint64_t v) { return static_cast<unsigned long long>(v); };
    std::printf(
        "%5u %8llu %8llu %9llu %8llu %8llu %8llu %8llu %8llu %8llu %8llu %8llu %8llu "
        "%7llu %7llu\n",
        e.node_ids()[i], u(c.handed_in), u(c.transmitted), u(c.delivered), u(c.lost[0]),
        u(c.lost[1]), u(c.lost[2]), u(c.lost[3]), u(c.lost[4]), u(c.queue_dropped), u(c.pending()),
        u(c.received), u(c.rx_crc_failures), u(c.location_updates), u(c.location_errors));
  }
  std::fflush(stdout);
}

/// One line per external node: how often its process joined, was dropped and
/// timed out, so that a flaky flowgraph shows at a glance.
void print_external_summary(const external::ExternalRuntime& ext) {
  const nlohmann::json j = ext.summary();
  std::printf("external transceivers (%s): %llu connection(s) refused, %llu child restart(s)\n",
              j["socket"].get<std::string>().c_str(),
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

/// Lock-step needs everyone at the start: waits (Ctrl-C aware) until every
/// external node has joined or external.start_timeout_s passed. Nodes that did
/// not join start silent and may join later. False when interrupted.
bool wait_for_external_nodes(const external::ExternalRuntime& ext, const scenario::Scenario& s,
                             const sigset_t& signals) {
  std::printf("rfsitl: external socket %s; waiting up to %.0f s for the external nodes to join\n",
              ext.socket_path().c_str(), s.external.start_timeout_s);
  std::fflush(stdout);
  const timespec poll{0, 20'000'000};
  for (double waited = 0.0;; waited += 0.02) {
    const auto missing = ext.hub().never_joined();
    if (missing.empty()) return true;
    const int sig = sigtimedwait(&signals, nullptr, &poll);
    if (sig == SIGINT || sig == SIGTERM) {
      std::printf("rfsitl: interrupted while waiting for external nodes\n");
      return false;
    }
    if (waited >= s.external.start_timeout_s) {
      std::string ids;
      for (const NodeId id : missing) ids += " " + std::to_string(id);
      std::printf("rfsitl: starting without node(s)%s: silent until they join\n", ids.c_str());
      return true;
    }
  }
}

int run(const RunOptions& o) {
  scenario::Scenario s;
  try {
    s = build_scenario(o);
  } catch (const scenario::ScenarioError& e) {
    std::fprintf(stderr, "rfsitl run: %s\n", e.what());
    return 2;
  }
  // Signals are taken synchronously by this thread only; block them before any
  // other thread exists so that every thread inherits the mask.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  io::ServerConfig sc{
      s.ports.bind_address, s.ports.net_base, s.ports.loc_base, s.channel.origin, {}};
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    if (s.phy_of(i).type == "external") sc.external_net_ports.push_back(s.nodes[i].id);
  }
  auto servers = io::make_node_servers(sc);
  std::unique_ptr<external::ExternalRuntime> external;
  std::unique_ptr<engine::Engine> engine;
  // Observers of the engine: destroyed before it.
  std::unique_ptr<monitor::PcapTrace> pcap;
  std::unique_ptr<monitor::SigmfRecorder> sigmf;
  std::unique_ptr<monitor::Dashboard> dashboard;
  try {
    external = external::ExternalRuntime::create(s);
    engine = engine::make_engine(
        s, *servers, external ? external->transceiver_factory() : engine::TransceiverFactory{});
    if (!o.pcap_path.empty()) {
      pcap = monitor::make_pcap_trace(monitor::PcapTraceSettings{
          o.pcap_path, static_cast<std::uint64_t>(o.pcap_max_mb * 1024 * 1024), o.pcap_files,
          s.timing.sample_rate_hz, 10.0 * std::log10(std::max(s.channel.noise_variance, 1e-30))});
      engine->add_observer(*pcap);
    }
    if (!o.sigmf_dir.empty()) {
      monitor::SigmfSettings ss;
      ss.directory = o.sigmf_dir;
      for (const unsigned id : o.sigmf_nodes) ss.nodes.push_back(static_cast<NodeId>(id));
      if (ss.nodes.empty()) {
        for (const auto& n : s.nodes) ss.nodes.push_back(n.id);
      }
      ss.start_s = o.sigmf_start_s;
      ss.duration_s = o.sigmf_duration_s;
      ss.max_bytes = static_cast<std::uint64_t>(o.sigmf_max_mb * 1024 * 1024);
      sigmf = monitor::make_sigmf_recorder(ss, s);
      engine->add_observer(*sigmf);
    }
    servers->start(*engine);
    if (!o.no_dashboard) {
      monitor::DashboardSettings ds;
      ds.bind_address = s.ports.bind_address;
      ds.port = o.dashboard_port.value_or(ds.port);
      ds.fall_back_to_any_port = !o.dashboard_port;
      ds.control = o.dashboard_control;
      dashboard = monitor::start_dashboard(ds, s, *engine);
    }
    if (external) external->start_children();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rfsitl run: %s\n", e.what());
    return 2;
  }
  print_banner(s, sc);
  if (dashboard) {
    std::printf("rfsitl: dashboard %s (moving nodes %s)\n", dashboard->url().c_str(),
                o.dashboard_control ? "allowed" : "off; --dashboard-control allows it");
    std::fflush(stdout);
  }
  if (external && !wait_for_external_nodes(*external, s, signals)) {
    print_summary(*engine);
    return 1;
  }
  std::printf("rfsitl: ready, listening on %zu net ports and %zu location ports (Ctrl-C to stop)\n",
              s.nodes.size(), s.nodes.size());
  std::fflush(stdout);

  std::atomic<bool> stop{false};
  std::atomic<bool> finished{false};
  std::thread engine_thread([&] {
    engine->run(stop);
    finished.store(true);
  });

  const double stats_every = s.engine.stats_interval_s;
  double next_stats = stats_every;
  const timespec poll{0, 50'000'000};
  while (!finished.load()) {
    const int sig = sigtimedwait(&signals, nullptr, &poll);
    if (sig == SIGINT || sig == SIGTERM) {
      std::printf("\nrfsitl: %s received, shutting down\n", sig == SIGINT ? "SIGINT" : "SIGTERM");
      break;
    }
    if (stats_every > 0 && engine->status().wall_s >= next_stats) {
      print_stats_line(*engine);
      next_stats += stats_every;
    }
  }
  stop.store(true);
  engine_thread.join();
  servers->stop();
  if (sigmf) sigmf->finish();
  if (pcap) {
    pcap->flush();
    std::printf("rfsitl: pcap trace %s: %llu frame events\n", o.pcap_path.c_str(),
                static_cast<unsigned long long>(pcap->events_written()));
  }
  print_summary(*engine);
  if (external) print_external_summary(*external);
  if (!o.summary_json.empty()) {
    std::ofstream out(o.summary_json);
    nlohmann::json j = monitor::stats_json(s, *engine);
    if (external) j["external"] = external->summary();
    out << j.dump(2) << "\n";
    if (!out) {
      std::fprintf(stderr, "rfsitl run: cannot write %s\n", o.summary_json.c_str());
      return 1;
    }
  }
  return 0;
}

}  // namespace

std::function<int()> add_run_command(CLI::App& parent) {
  auto opts = std::make_shared<RunOptions>();
  CLI::App* cmd =
      parent.add_subcommand("run", "Run the emulator: one net port and one location port per node");
  cmd->add_option("scenario", opts->scenario_path, "Scenario file (YAML); see scenarios/")
      ->check(CLI::ExistingFile);
  cmd->add_option(
         "--nodes", opts->nodes,
         "Nodes in the default formation where every link decodes (1..250; 6 without a scenario)")
      ->check(CLI::Range(1, 250));
  cmd->add_option("--net-base", opts->net_base, "Net port base: node n listens on base + 10 n");
  cmd->add_option("--loc-base", opts->loc_base, "Location port base: base + 10 n");
  cmd->add_option("--bind", opts->bind, "Address to listen on (default 127.0.0.1)");
  cmd->add_option("--mode", opts->mode, "realtime or virtual")
      ->check(CLI::IsMember({"realtime", "virtual"}));
  cmd->add_option("--speed", opts->speed, "Real-time speed factor (virtual s per wall s)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--duration", opts->duration_s, "Virtual seconds to run (0: until Ctrl-C)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--sample-rate", opts->sample_rate_hz, "Sample rate fs in Hz")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--tick", opts->tick_samples, "Samples per lock-step tick (B)")
      ->check(CLI::Range(1U, 1U << 20));
  cmd->add_option("--seed", opts->seed, "Seed of the noise sources");
  cmd->add_option("--threads", opts->threads, "Worker threads (0: one per core)");
  cmd->add_option("--noise-db", opts->noise_db, "Noise power 10 log10(sigma^2) in dB");
  cmd->add_option("--stats-interval", opts->stats_interval_s,
                  "Seconds between stats lines (0: off)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--phy", opts->phy_type,
                  "Transceiver type of every node without its own phy (gmsk, gmsk-liquid, ofdm, "
                  "dsss, external)");
  cmd->add_option("--arch", opts->arch,
                  "Where built-in transceivers run: threads (in the emulator) or split (one "
                  "`rfsitl node` process each)")
      ->check(CLI::IsMember({"threads", "split"}));
  cmd->add_option("--external-socket", opts->external_socket,
                  "Unix socket for external transceivers (default /tmp/rfsitl-<net-base>.sock)");
  cmd->add_option("--external-timeout", opts->external_timeout_s,
                  "Seconds an external transceiver may take to answer before it is dropped")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--pcap", opts->pcap_path,
                  "Write every frame event to this pcapng file (Wireshark; docs/traces.md)");
  cmd->add_option("--pcap-max-mb", opts->pcap_max_mb, "Rotate the pcap file beyond this size")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--pcap-files", opts->pcap_files, "pcap files kept when rotating")
      ->check(CLI::Range(1U, 1000U));
  cmd->add_option("--sigmf", opts->sigmf_dir,
                  "Record received I/Q in SigMF into this directory (docs/traces.md)");
  cmd->add_option("--sigmf-nodes", opts->sigmf_nodes, "Node ids to record (default: all)")
      ->delimiter(',');
  cmd->add_option("--sigmf-start", opts->sigmf_start_s, "Virtual second the recording starts")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--sigmf-duration", opts->sigmf_duration_s, "Virtual seconds to record")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--sigmf-max-mb", opts->sigmf_max_mb, "Largest recording per node")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--dashboard-port", opts->dashboard_port,
                  "Port of the web dashboard (default 15700, or any free port if taken; 0: any)");
  cmd->add_flag("--no-dashboard", opts->no_dashboard, "Do not serve the web dashboard");
  cmd->add_flag("--dashboard-control", opts->dashboard_control,
                "Let dashboard viewers move nodes (off by default)");
  cmd->add_flag("--no-skip", opts->no_skip, "Run every receiver every tick (no silence skipping)");
  cmd->add_flag("--shared-noise", opts->shared_noise,
                "One noise source for all receivers (the paper's setup)");
  cmd->add_option("--summary-json", opts->summary_json,
                  "Write the final counters as JSON to this file");
  return [opts] { return run(*opts); };
}

}  // namespace rfsitl::app
