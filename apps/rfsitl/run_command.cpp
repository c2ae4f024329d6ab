/// `rfsitl run`: load a scenario, open the ports, run the engine until a signal
/// or the scenario's duration, then print the per-node summary.
#include <pthread.h>
#include <signal.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "distributed_run.hpp"
#include "live_sources.hpp"
#include "rfsitl/agent_port/ip_ports.hpp"
#include "rfsitl/agent_port/net_ports.hpp"
#include "rfsitl/engine/engine.hpp"
#include "rfsitl/external/external_runtime.hpp"
#include "rfsitl/io/bind_address.hpp"
#include "rfsitl/monitor/control_token.hpp"
#include "rfsitl/monitor/dashboard.hpp"
#include "rfsitl/monitor/json_text.hpp"
#include "rfsitl/monitor/live_view.hpp"
#include "rfsitl/monitor/pcap_trace.hpp"
#include "rfsitl/monitor/sigmf_recorder.hpp"
#include "rfsitl/registry/position_source_registry.hpp"
#include "rfsitl/scenario/default_formation.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"
#include "run_report.hpp"

namespace rfsitl::app {
namespace {

/// A flag that sets a scenario setting. Its value goes through the scenario
/// file's own reader and rules (scenario::apply_setting), so the command line
/// and the file accept exactly the same values, and errors name the flag.
struct SettingFlag {
  const char* flag;
  const char* key;   ///< dotted scenario key
  const char* type;  ///< what --help shows for the value (UINT, FLOAT, ...)
  const char* help;  ///< says the unit
  std::string (*default_of)(const scenario::Scenario&);  ///< for --help
};

std::string number(double v) {
  std::array<char, 32> buf{};
  return {buf.data(), std::to_chars(buf.data(), buf.data() + buf.size(), v).ptr};
}

using S = const scenario::Scenario&;
const SettingFlag kSettingFlags[] = {
    {"--net-base", "ports.net_base", "UINT", "Net port base: node n listens on base + 10 n",
     [](S d) { return number(d.ports.net_base); }},
    {"--loc-base", "ports.loc_base", "UINT", "Location port base: base + 10 n",
     [](S d) { return number(d.ports.loc_base); }},
    {"--bind", "ports.bind", "HOST",
     "Address or host name every server listens on (e.g. localhost)",
     [](S d) { return d.ports.bind_address; }},
    {"--mode", "time.mode", "{realtime,virtual}",
     "realtime or virtual (as fast as possible, deterministic)",
     [](S) { return std::string("realtime"); }},
    {"--speed", "time.speed", "FLOAT", "Real-time speed factor: virtual seconds per wall second",
     [](S d) { return number(d.timing.speed); }},
    {"--duration", "time.duration_s", "FLOAT", "Virtual seconds to run; 0: until Ctrl-C",
     [](S d) { return number(d.timing.duration_s); }},
    {"--sample-rate", "time.sample_rate_hz", "FLOAT", "Sample rate fs in Hz",
     [](S d) { return number(d.timing.sample_rate_hz); }},
    {"--tick", "time.tick_samples", "UINT", "Samples per lock-step tick (B)",
     [](S d) { return number(d.timing.tick_samples); }},
    {"--tick-us", "time.tick_us", "FLOAT",
     "Tick by duration in us, at the sample rate (a whole number of samples); instead of --tick",
     [](S d) { return number(1e6 * d.timing.tick_samples / d.timing.sample_rate_hz); }},
    {"--seed", "seed", "UINT", "Seed of the noise sources",
     [](S d) { return number(double(d.seed)); }},
    {"--threads", "engine.threads", "UINT", "Worker threads; 0: one per core",
     [](S d) { return number(d.engine.threads); }},
    {"--noise-db", "channel.noise_power_db", "FLOAT",
     "Noise power 10 log10(sigma^2) in dB, -300..300",
     [](S d) { return number(10.0 * std::log10(d.channel.noise_variance)); }},
    {"--stats-interval", "engine.stats_interval_s", "FLOAT",
     "Wall seconds between stats lines; 0: off",
     [](S d) { return number(d.engine.stats_interval_s); }},
    {"--phy", "phy.type", "NAME",
     "Transceiver of every node without its own phy (rfsitl describe phy lists them)",
     [](S d) { return d.phy.type; }},
    {"--external-socket", "external.socket", "PATH", "Unix socket for external transceivers",
     [](S) { return std::string("/tmp/rfsitl-<net-base>.sock"); }},
    {"--external-timeout", "external.reply_timeout_s", "FLOAT",
     "Seconds an external transceiver may take to answer before it is dropped",
     [](S d) { return number(d.external.reply_timeout_s); }},
};
constexpr std::size_t kNumSettingFlags = std::size(kSettingFlags);

struct RunOptions {
  std::string scenario_path;
  std::optional<std::size_t> nodes;
  std::array<std::optional<std::string>, kNumSettingFlags> settings;  ///< as typed
  std::optional<std::string> arch;
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
  std::optional<std::string> dashboard_token;       ///< --dashboard-token
  std::optional<std::string> dashboard_token_file;  ///< --dashboard-token-file
  bool no_skip = false;
  bool shared_noise = false;
  bool ip = false;
  std::optional<std::string> mac;  ///< --mac NAME
  std::string summary_json;
  /// The position sources' flags (--mavlink ENDPOINT), as typed: one per
  /// source that declares one, in the registry's order.
  std::vector<std::pair<const position::PositionSourceComponent*, std::optional<std::string>>>
      source_flags;
};

// A file refuses tick_samples beside tick_us; so does the command line.
void refuse_both_ticks(const RunOptions& o) {
  const auto given = [&o](std::string_view flag) {
    for (std::size_t i = 0; i < kNumSettingFlags; ++i) {
      if (kSettingFlags[i].flag == flag) return o.settings[i].has_value();
    }
    return false;
  };
  if (given("--tick") && given("--tick-us")) {
    throw scenario::ScenarioError("--tick-us: give the tick as --tick or as --tick-us, not both");
  }
}

scenario::Scenario build_scenario(const RunOptions& o) {
  scenario::Scenario s;
  if (!o.scenario_path.empty()) {
    if (o.nodes) {
      throw scenario::ScenarioError(
          "--nodes builds the default formation and cannot be combined with a scenario file (" +
          o.scenario_path + " lists its own nodes)");
    }
    s = scenario::load_scenario_file(o.scenario_path);
  } else {
    // Placed now so that every flag is checked against the nodes it will
    // apply to; placed again below, once the channel flags are known.
    s.nodes = scenario::default_formation(o.nodes.value_or(6), s.channel);
    s.name = "default-formation";
  }
  refuse_both_ticks(o);
  for (std::size_t i = 0; i < kNumSettingFlags; ++i) {
    if (const auto& v = o.settings[i]) {
      scenario::apply_setting(s, kSettingFlags[i].key, *v, std::string(kSettingFlags[i].flag));
    }
  }
  for (const auto& [source, value] : o.source_flags) {
    if (value) follow_source(s, *source, *value);
  }
  if (o.no_skip) scenario::apply_setting(s, "engine.skip_idle_receivers", "false", "--no-skip");
  if (o.shared_noise) scenario::apply_setting(s, "channel.shared_noise", "true", "--shared-noise");
  if (o.ip) scenario::apply_setting(s, "ip.enabled", "true", "--ip");
  if (o.mac) scenario::apply_setting(s, "mac.type", *o.mac, "--mac");
  if (o.scenario_path.empty()) s.nodes = scenario::default_formation(s.nodes.size(), s.channel);
  if (o.arch) {
    // Every built-in transceiver moves: threads = in the emulator, split = one
    // `rfsitl node` process each. External programs stay what they are.
    const auto process =
        *o.arch == "split" ? scenario::Process::kChild : scenario::Process::kInline;
    s.phy.process = process;
    for (auto& n : s.nodes) {
      if (n.phy) n.phy->process = process;
    }
  }
  scenario::validate_scenario(s);
  return s;
}

/// What every rank of a distributed run must have been given alike: the
/// scenario file's bytes and the options.
std::string run_fingerprint(const RunOptions& o) {
  std::string text;
  if (!o.scenario_path.empty()) {
    std::ifstream in(o.scenario_path, std::ios::binary);
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const auto add = [&text](const std::string& v) { text += '\0' + v; };
  add(std::to_string(o.nodes.value_or(0)));
  for (const auto& v : o.settings) add(v.value_or("-"));
  add(o.arch.value_or("-"));
  add(o.mac.value_or("-"));
  for (const auto& [source, value] : o.source_flags) add(value.value_or("-"));
  add(std::to_string(o.ip) + std::to_string(o.no_skip) + std::to_string(o.shared_noise));
  return text;
}

/// Lock-step needs everyone at the start: waits (Ctrl-C aware) until every
/// external node served here has joined or external.start_timeout_s passed.
/// Nodes that did not join start silent and may join later. False when
/// interrupted. `who` starts the lines ("rfsitl", or "rfsitl: rank R").
bool wait_for_external_nodes(const external::ExternalRuntime& ext, const scenario::Scenario& s,
                             const sigset_t& signals, const std::string& who) {
  const auto id_list = [](const std::vector<NodeId>& ids) {
    std::string text;
    for (const NodeId id : ids) text += " " + std::to_string(id);
    return text;
  };
  std::printf("%s: external socket %s; waiting up to %.0f s for the external node(s)%s to join\n",
              who.c_str(), ext.socket_path().c_str(), s.external.start_timeout_s,
              id_list(ext.hub().never_joined()).c_str());
  std::fflush(stdout);
  const timespec poll{0, 20'000'000};
  for (double waited = 0.0;; waited += 0.02) {
    const auto missing = ext.hub().never_joined();
    if (missing.empty()) return true;
    const int sig = sigtimedwait(&signals, nullptr, &poll);
    if (sig == SIGINT || sig == SIGTERM) {
      std::printf("%s: interrupted while waiting for external nodes\n", who.c_str());
      return false;
    }
    if (waited >= s.external.start_timeout_s) {
      std::printf("%s: starting without node(s)%s: silent until they join\n", who.c_str(),
                  id_list(missing).c_str());
      return true;
    }
  }
}

/// The dashboard's control token: the user's (flag or file), or one drawn at
/// random when control is on and the dashboard is reachable beyond this
/// machine; "" when none is needed. Sets `drawn` when it was drawn here.
/// Throws std::runtime_error naming the flag when the user's is unusable.
std::string dashboard_control_token(const RunOptions& o, const std::string& bind_address,
                                    bool& drawn) {
  drawn = false;
  std::string token;
  std::string flag;
  if (o.dashboard_token) {
    token = *o.dashboard_token;
    flag = "--dashboard-token";
  } else if (o.dashboard_token_file) {
    flag = "--dashboard-token-file " + *o.dashboard_token_file;
    std::ifstream in(*o.dashboard_token_file);
    if (!in) throw std::runtime_error(flag + ": cannot read: " + std::strerror(errno));
    std::getline(in, token);  // the first line; an editor's newline is not part of it
    while (!token.empty() && (token.back() == '\r' || token.back() == ' ')) token.pop_back();
  }
  if (!flag.empty()) {
    if (const std::string why = monitor::control_token_problem(token); !why.empty()) {
      throw std::runtime_error(flag + ": the token " + why);
    }
    return token;
  }
  if (!o.dashboard_control || o.no_dashboard || monitor::bind_is_loopback(bind_address)) return "";
  drawn = true;
  return monitor::generate_control_token();
}

int run(const RunOptions& o) {
  scenario::Scenario s;
  try {
    s = build_scenario(o);
  } catch (const scenario::ScenarioError& e) {
    std::fprintf(stderr, "rfsitl run: %s\n", e.what());
    return 2;
  }
  RunRanks ranks;
  if (const auto why = start_ranks(s, run_fingerprint(o), ranks)) {
    std::fprintf(stderr, "rfsitl run: %s\n", why->c_str());
    return 2;
  }
  // In a distributed run rank 0 speaks for the run: the banner, the stats,
  // the summary and its JSON, the dashboard.
  const bool speaks = ranks.rank == 0;
  std::string bind_address;
  try {
    bind_address = io::resolve_bind_address(s.ports.bind_address);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rfsitl run: ports.bind: %s\n", e.what());
    return 2;
  }
  // The token too: a token file that cannot be used fails before the ports open.
  bool token_drawn = false;
  std::string control_token;
  try {
    control_token = dashboard_control_token(o, bind_address, token_drawn);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rfsitl run: %s\n", e.what());
    return 2;
  }
  const bool token_needed = !control_token.empty();
  // Output files are opened now: a path that cannot be written fails before
  // the run, not after it with the results lost.
  std::ofstream summary_out;
  if (!o.summary_json.empty() && speaks) {
    summary_out.open(o.summary_json);
    if (!summary_out) {
      std::fprintf(stderr, "rfsitl run: --summary-json %s: cannot write: %s\n",
                   o.summary_json.c_str(), std::strerror(errno));
      return 2;
    }
  }
  // Signals are taken synchronously by this thread only; block them before any
  // other thread exists so that every thread inherits the mask.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  agent_port::NetPortsConfig sc{bind_address, s.ports.net_base, {}, {}};
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    if (s.phy_of(i).external_program()) sc.external_net_ports.push_back(s.nodes[i].id);
    if (!ranks.here(i)) sc.elsewhere.push_back(s.nodes[i].id);
  }
  auto servers = agent_port::make_net_ports(sc);
  // With IP, Ethernet frames go to the nodes' interfaces and the rest on to
  // the net ports. Made now: without the privileges nothing else starts. In a
  // distributed run each rank serves its own nodes, one rank per host claims
  // the namespaces' prefix, and all wait for the claims (agree() is a
  // barrier) before any makes a namespace.
  std::unique_ptr<agent_port::IpPorts> ipnet;
  if (s.ip.enabled) {
    std::string error;
    try {
      ipnet = agent_port::make_ip_ports(s, *servers,
                                        {ranks.here_mask(s.nodes.size()), ranks.first_on_host()});
    } catch (const std::exception& e) {
      error = e.what();
    }
    if (const auto why = agree(ranks, error)) {
      std::fprintf(stderr, "rfsitl run: %s\n", why->c_str());
      return 2;
    }
  }
  engine::FrameSink& sink = ipnet ? static_cast<engine::FrameSink&>(*ipnet) : *servers;
  std::unique_ptr<external::ExternalRuntime> external;
  std::unique_ptr<engine::Engine> engine;
  // Observers of the engine: destroyed before it.
  std::unique_ptr<monitor::PcapTrace> pcap;
  std::unique_ptr<monitor::SigmfRecorder> sigmf;
  // Live sources report into the engine and the dashboard reads them: declared
  // between the two so that they are destroyed in that order.
  std::unique_ptr<LiveSources> sources;
  std::unique_ptr<monitor::Dashboard> dashboard;
  // The other ranks' side of rank 0's dashboard: what their nodes showed.
  std::unique_ptr<monitor::LiveView> rank_view;
  std::string drawn_token_url;
  // A distributed run's ranks each trace their own nodes, into files of their own.
  const std::string pcap_path =
      ranks.distributed() ? rank_file_name(o.pcap_path, ranks.rank) : o.pcap_path;
  std::string setup_error;
  try {
    // A distributed run's ranks each serve their own external nodes, on a
    // socket of their own (rank_file_name: /tmp/rfsitl-<base>.rank<R>.sock).
    external = external::ExternalRuntime::create(
        s, {ranks.here_mask(s.nodes.size()),
            ranks.distributed() ? rank_file_name(external::external_socket_path(s), ranks.rank)
                                : std::string()});
    engine = engine::make_engine(
        s, sink, external ? external->transceiver_factory() : engine::TransceiverFactory{},
        ranks.distribution());
    if (!o.pcap_path.empty()) {
      pcap = monitor::make_pcap_trace(monitor::PcapTraceSettings{
          pcap_path, static_cast<std::uint64_t>(o.pcap_max_mb * 1024 * 1024), o.pcap_files,
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
      std::erase_if(ss.nodes, [&](NodeId id) { return !ranks.here(*engine->index_of(id)); });
      ss.start_s = o.sigmf_start_s;
      ss.duration_s = o.sigmf_duration_s;
      ss.max_bytes = static_cast<std::uint64_t>(o.sigmf_max_mb * 1024 * 1024);
      sigmf = monitor::make_sigmf_recorder(ss, s);
      engine->add_observer(*sigmf);
    }
    sources =
        std::make_unique<LiveSources>(s, position::SourceContext{bind_address, s.ports.loc_base},
                                      ranks.here_mask(s.nodes.size()));
    sources->start(*engine);
    if (!o.no_dashboard && speaks) {
      monitor::DashboardSettings ds;
      ds.bind_address = bind_address;
      ds.port = o.dashboard_port.value_or(ds.port);
      ds.fall_back_to_any_port = !o.dashboard_port;
      ds.control = o.dashboard_control;
      ds.control_token = control_token;
      ds.sources = sources->status_fn();
      dashboard = monitor::start_dashboard(ds, s, *engine);
      if (token_drawn) drawn_token_url = dashboard->url() + "?token=" + control_token;
    } else if (!o.no_dashboard && ranks.distributed()) {
      rank_view = std::make_unique<monitor::LiveView>(engine->node_ids());
      engine->add_observer(*rank_view);
    }
    // Last: a frame an agent hands in reaches every observer (the traces, the
    // dashboard's live view) from the net ports' thread, so all of them are
    // added before the ports open (add_observer is not thread-safe).
    servers->start(*engine);
    if (ipnet) ipnet->start(*engine);
    if (external) external->start_children();
  } catch (const std::exception& e) {
    setup_error = e.what();
  }
  // Every rank starts, or none does (one process: its own verdict).
  if (const auto why = agree(ranks, setup_error)) {
    std::fprintf(stderr, "rfsitl run: %s\n", why->c_str());
    // Nothing ran: leave no empty summary or trace behind to be mistaken for a
    // run's results.
    if (summary_out.is_open()) {
      summary_out.close();
      std::remove(o.summary_json.c_str());
    }
    if (pcap) std::remove(pcap_path.c_str());  // unlinked; the object closes it later
    return 2;
  }
  if (speaks) {
    std::vector<std::string> served_by(s.nodes.size());
    for (std::size_t i = 0; i < s.nodes.size(); ++i) {
      if (ranks.here(i)) continue;
      const std::size_t r = ranks.owner[i];
      served_by[i] = "rank " + std::to_string(r) +
                     (r < ranks.hosts.size() ? " (host " + ranks.hosts[r] + ")" : "");
    }
    print_banner(s, sc, *sources, *engine, served_by);
  }
  if (ranks.distributed() && speaks) {
    std::fputs(describe_ranks(s, ranks).c_str(), stdout);
    std::fflush(stdout);
  }
  // Every rank's interfaces, which rank 0 prints and puts in the summary.
  std::vector<agent_port::IpNodeInfo> ip_nodes;
  nlohmann::json ip_stale = nlohmann::json::array();
  if (ipnet) {
    const nlohmann::json mine = ipnet->summary();
    for (const std::string& text :
         gather_texts(ranks, nlohmann::json{mine["nodes"], mine["removed_stale"]}.dump())) {
      const nlohmann::json theirs = nlohmann::json::parse(text);
      for (auto& n : agent_port::ip_nodes_from_json(theirs[0])) ip_nodes.push_back(std::move(n));
      for (const auto& name : theirs[1]) ip_stale.push_back(name);
    }
    std::sort(ip_nodes.begin(), ip_nodes.end(), [&](const auto& a, const auto& b) {
      return engine->index_of(a.id) < engine->index_of(b.id);
    });
    if (speaks) print_ip_banner(ip_nodes);
  }
  if (dashboard) {
    const char* control = !o.dashboard_control ? "off; --dashboard-control allows it"
                          : !token_needed      ? "allowed"
                          : token_drawn        ? "only with the control token of the URL below"
                                               : "only with the control token you gave";
    std::printf("rfsitl: dashboard %s (moving nodes %s)\n", dashboard->url().c_str(), control);
    if (token_drawn) {
      // Printed once: the dashboard is reachable beyond this machine, so the
      // token is what keeps others on the network from moving nodes.
      std::printf(
          "rfsitl: dashboard control URL (its token, drawn for this run, lets whoever has it move "
          "nodes; viewing needs none): %s\n",
          drawn_token_url.c_str());
    }
    std::fflush(stdout);
  }
  const std::string who =
      ranks.distributed() ? "rfsitl: rank " + std::to_string(ranks.rank) : "rfsitl";
  if (external && external->serves_any() && !wait_for_external_nodes(*external, s, signals, who)) {
    print_summary(*engine);
    return 1;
  }
  const std::size_t own_net_ports =
      s.nodes.size() - sc.external_net_ports.size() - sc.elsewhere.size();
  if (speaks) {
    std::printf(
        "rfsitl: ready, listening on %zu net port(s) and %zu location port(s)%s; %s\n",
        own_net_ports, s.nodes.size() - sc.elsewhere.size(),
        ranks.distributed() ? " on rank 0 (the others on theirs)" : "",
        s.timing.duration_s > 0 ? "stops after the duration or at Ctrl-C" : "Ctrl-C to stop");
  }
  if (s.timing.mode == scenario::TimeMode::kVirtual && speaks) {
    // Virtual time does not wait for the wall clock, so live agents cannot keep
    // up with it: their frames enter at whatever tick the engine has reached.
    std::printf(
        "rfsitl: virtual time runs as fast as the machine allows, not in step with the agents "
        "on the ports; the scenario's traffic: is what makes a run reproducible (%zu item(s))\n",
        s.traffic.size());
  }
  std::fflush(stdout);

  std::atomic<bool> stop{false};
  std::atomic<bool> finished{false};
  std::string engine_error;  // written by the engine's thread before `finished`
  std::thread engine_thread([&] {
    try {
      engine->run(stop);
    } catch (const std::exception& e) {
      // A distributed run's exchange failed (the run cannot go on).
      engine_error = e.what();
    }
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
      if (speaks) print_stats_line(*engine);
      next_stats += stats_every;
    }
  }
  stop.store(true);
  if (ranks.distributed()) {
    // The ranks stop together at the next tick's exchange; a rank whose peers
    // died waits there for ever (Open MPI does not survive a lost rank), so
    // after a while it reports what it has and leaves.
    for (int waited_ms = 0; !finished.load() && waited_ms < 10'000; waited_ms += 50) {
      const timespec step{0, 50'000'000};
      nanosleep(&step, nullptr);
    }
    if (!finished.load()) {
      print_partial_summary(*engine, ranks);
      std::_Exit(1);
    }
  }
  engine_thread.join();
  if (!engine_error.empty()) {
    std::fprintf(stderr, "rfsitl run: rank %zu: %s\n", ranks.rank, engine_error.c_str());
    print_partial_summary(*engine, ranks);
    std::_Exit(1);
  }
  sources->stop();
  if (ipnet) ipnet->stop();
  servers->stop();
  if (sigmf) sigmf->finish();
  if (pcap) {
    pcap->flush();
    const nlohmann::json trace = pcap->summary();
    const std::string stopped =
        trace["stopped"].get<bool>() ? "; stopped early: " + trace["error"].get<std::string>() : "";
    std::printf("rfsitl: pcap trace %s: %llu frame events%s\n", o.pcap_path.c_str(),
                static_cast<unsigned long long>(pcap->events_written()), stopped.c_str());
  }
  if (sigmf) {
    const nlohmann::json recording = sigmf->summary();
    for (const auto& n : recording["nodes"]) {
      if (n["stopped"].get<bool>()) {
        std::printf("rfsitl: SigMF recording %s stopped early: %s\n",
                    n["data"].get<std::string>().c_str(), n["error"].get<std::string>().c_str());
      }
    }
  }
  // Collective in a distributed run: every rank's external nodes.
  const nlohmann::json external_summary =
      external ? merge_external_summaries(gather_texts(ranks, external->summary().dump()), *engine)
               : nlohmann::json();
  if (!speaks) return 0;
  print_summary(*engine);
  if (ranks.distributed()) {
    const double tick_s = s.timing.tick_samples / s.timing.sample_rate_hz;
    std::printf("distributed run, %zu ranks:\n%s", ranks.size,
                rank_summary(*engine, tick_s).c_str());
    std::fflush(stdout);
  }
  if (external) print_external_summary(external_summary);
  if (summary_out.is_open()) {
    const nlohmann::json j =
        summary_json({s, *engine, *sources, ranks, external ? &external_summary : nullptr,
                      pcap.get(), sigmf.get(), ipnet.get(), ip_nodes, ip_stale});
    summary_out << monitor::json_text(j, 2) << "\n";
    summary_out.flush();
    if (!summary_out) {
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
  // No CLI::ExistingFile: the loader's message names the file and the reason.
  cmd->add_option("scenario", opts->scenario_path,
                  "Scenario file (YAML); see scenarios/. A bare name that is not a file here "
                  "is looked up among the installed scenarios (share/rfsitl/scenarios)")
      ->type_name("PATH")
      ->transform(CLI::Validator(
          [](std::string& path) {
            path = scenario_file(path);
            return std::string();
          },
          "", "installed scenario"));
  cmd->add_option(
         "--nodes", opts->nodes,
         "Nodes in the default formation where every link decodes (1..254; 6 without a scenario)")
      ->check(CLI::Range(1, int{kMaxNodeId}));
  const scenario::Scenario defaults;
  for (std::size_t i = 0; i < kNumSettingFlags; ++i) {
    cmd->add_option(kSettingFlags[i].flag, opts->settings[i], kSettingFlags[i].help)
        ->type_name(kSettingFlags[i].type)
        ->default_str(kSettingFlags[i].default_of(defaults));
  }
  cmd->add_option("--arch", opts->arch,
                  "Where built-in transceivers run: threads (in the emulator) or split (one "
                  "`rfsitl node` process each)")
      ->check(CLI::IsMember({"threads", "split"}));
  cmd->add_option("--pcap", opts->pcap_path,
                  "Write every frame event to this pcapng file (Wireshark; docs/traces.md)")
      ->type_name("PATH");
  cmd->add_option("--pcap-max-mb", opts->pcap_max_mb, "Rotate the pcap file beyond this size (MiB)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--pcap-files", opts->pcap_files, "pcap files kept when rotating")
      ->check(CLI::Range(1U, 1000U))
      ->capture_default_str();
  cmd->add_option("--sigmf", opts->sigmf_dir,
                  "Record received I/Q in SigMF into this directory (docs/traces.md)")
      ->type_name("DIR");
  cmd->add_option("--sigmf-nodes", opts->sigmf_nodes,
                  "Node ids to record, e.g. 2,5 (default: all; a recorded receiver runs every "
                  "tick of the window, so fewer nodes cost less)")
      ->delimiter(',');
  cmd->add_option("--sigmf-start", opts->sigmf_start_s, "Virtual second the recording starts")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--sigmf-duration", opts->sigmf_duration_s, "Virtual seconds to record")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--sigmf-max-mb", opts->sigmf_max_mb, "Largest recording per node (MiB)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--dashboard-port", opts->dashboard_port,
                  "Port of the web dashboard (default 15700, or any free port if taken; 0: any)");
  // Each position source's shorthand flag (--mavlink), as the source declares it.
  for (const position::PositionSourceComponent& source : position::position_source_components()) {
    if (!source.flag.flag.empty()) opts->source_flags.push_back({&source, std::nullopt});
  }
  for (auto& [source, value] : opts->source_flags) {
    cmd->add_option(source->flag.flag, value, source->flag.help)
        ->type_name(source->flag.value_name);
  }
  cmd->add_flag(
      "--ip", opts->ip,
      "IP on every node: a network namespace each (rfsitl-<net base>-<id>) with a TAP "
      "interface whose frames cross the radio channel (root; the scenario's ip: section)");
  cmd->add_option("--mac", opts->mac,
                  "Every node's MAC: none (the paper's: send when idle), csma (802.11 DCF-like) "
                  "or tdma (the scenario's mac: section sets their settings)")
      ->type_name("NAME");
  cmd->add_flag("--no-dashboard", opts->no_dashboard, "Do not serve the web dashboard");
  CLI::Option* control = cmd->add_flag("--dashboard-control", opts->dashboard_control,
                                       "Let dashboard viewers move nodes (off by default)");
  CLI::Option* token = cmd->add_option(
      "--dashboard-token", opts->dashboard_token,
      "Token that moving nodes requires (16-256 of A-Z a-z 0-9 . _ ~ -), as ?token= in the page "
      "URL or \"Authorization: Bearer\"; beyond loopback one is drawn and printed if not given "
      "(visible in ps: prefer --dashboard-token-file)");
  token->type_name("TOKEN")->needs(control);
  cmd->add_option("--dashboard-token-file", opts->dashboard_token_file,
                  "Read the control token from the first line of this file")
      ->type_name("PATH")
      ->needs(control)
      ->excludes(token);
  cmd->add_flag("--no-skip", opts->no_skip, "Run every receiver every tick (no silence skipping)");
  cmd->add_flag("--shared-noise", opts->shared_noise,
                "One noise source for all receivers (the paper's setup)");
  cmd->add_option("--summary-json", opts->summary_json,
                  "Write the final counters as JSON to this file (checked at start)")
      ->type_name("PATH");
  return [opts] { return run(*opts); };
}

}  // namespace rfsitl::app
