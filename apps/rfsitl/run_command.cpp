/// `rfsitl run`: the command line around a session (rfsitl/session/session.hpp):
/// its flags into the session's options, its steps, the signals, and what is
/// printed (run_report.hpp).
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

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "rfsitl/agent_port/net_ports.hpp"
#include "rfsitl/engine/engine.hpp"
#include "rfsitl/engine/preflight.hpp"
#include "rfsitl/external/external_runtime.hpp"
#include "rfsitl/monitor/control_token.hpp"
#include "rfsitl/monitor/dashboard.hpp"
#include "rfsitl/monitor/json_text.hpp"
#include "rfsitl/registry/position_source_registry.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"
#include "rfsitl/session/session.hpp"
#include "run_report.hpp"
#include "stop_signals.hpp"

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
  bool preflight = false;     ///< --preflight: measure, say, exit
  bool no_preflight = false;  ///< --no-preflight: no check at start
  bool ip = false;
  bool no_ports = false;           ///< --no-ports: no socket at all
  std::optional<std::string> mac;  ///< --mac NAME
  std::vector<std::string> set;    ///< --set KEY=VALUE, in order
  std::string summary_json;
  /// The position sources' flags (--mavlink ENDPOINT), as typed: one per
  /// source that declares one, in the registry's order.
  std::vector<std::pair<const position::PositionSourceComponent*, std::optional<std::string>>>
      source_flags;
};

/// The dashboard's control token the user gave (flag or file), checked; ""
/// when none was given (the session draws one where it is needed). Throws
/// std::runtime_error naming the flag when it is unusable.
std::string dashboard_control_token(const RunOptions& o) {
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
  }
  return token;
}

/// The session's options from the flags. The settings go in as the scenario
/// file would write them, each naming its flag, in the table's order and then
/// the switches'. Reads the dashboard's token file: a token that cannot be
/// used fails before anything starts. Throws std::runtime_error naming the flag.
session::SessionOptions session_options(const RunOptions& o) {
  session::SessionOptions so;
  so.scenario_path = o.scenario_path;
  so.nodes = o.nodes;
  for (std::size_t i = 0; i < kNumSettingFlags; ++i) {
    if (const auto& v = o.settings[i]) {
      so.settings.push_back({kSettingFlags[i].key, *v, kSettingFlags[i].flag});
    }
  }
  if (o.no_skip) so.settings.push_back({"engine.skip_idle_receivers", "false", "--no-skip"});
  if (o.shared_noise) so.settings.push_back({"channel.shared_noise", "true", "--shared-noise"});
  if (o.ip) so.settings.push_back({"ip.enabled", "true", "--ip"});
  if (o.mac) so.settings.push_back({"mac.type", *o.mac, "--mac"});
  // Last: a --set names its key, so it may override any flag above.
  for (const std::string& kv : o.set) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) {
      throw std::runtime_error("--set " + kv + ": give it as KEY=VALUE, e.g. --set " +
                               "channel.noise_power_db=-100");
    }
    so.settings.push_back({kv.substr(0, eq), kv.substr(eq + 1), "--set"});
  }
  so.ports = !o.no_ports;
  for (const auto& [source, value] : o.source_flags) {
    if (value) so.follow.push_back({source, *value});
  }
  if (o.arch) {
    // threads = in the emulator, split = one `rfsitl node` process each.
    so.transceivers = *o.arch == "split" ? scenario::Process::kChild : scenario::Process::kInline;
  }
  so.pcap = {o.pcap_path, static_cast<std::uint64_t>(o.pcap_max_mb * 1024 * 1024), o.pcap_files};
  so.sigmf.directory = o.sigmf_dir;
  for (const unsigned id : o.sigmf_nodes) so.sigmf.nodes.push_back(static_cast<NodeId>(id));
  so.sigmf.start_s = o.sigmf_start_s;
  so.sigmf.duration_s = o.sigmf_duration_s;
  so.sigmf.max_bytes = static_cast<std::uint64_t>(o.sigmf_max_mb * 1024 * 1024);
  so.dashboard.enabled = !o.no_dashboard;
  so.dashboard.port = o.dashboard_port;
  so.dashboard.control = o.dashboard_control;
  so.dashboard.control_token = dashboard_control_token(o);
  return so;
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

/// What is printed once every face is open, before the first tick: the
/// banner, the ranks, the IP interfaces, the dashboard; then the wait for
/// external nodes. False when interrupted during that wait.
bool announce(session::Session& run, const sigset_t& signals) {
  const scenario::Scenario& s = run.scenario();
  const session::RunRanks& ranks = run.ranks();
  engine::Engine& engine = run.engine();
  const agent_port::NetPortsConfig& sc = run.net_ports_config();
  const session::SessionOptions& o = run.options();
  if (run.speaks()) {
    std::vector<std::string> served_by(s.nodes.size());
    for (std::size_t i = 0; i < s.nodes.size(); ++i) {
      if (ranks.here(i)) continue;
      const std::size_t r = ranks.owner[i];
      served_by[i] = "rank " + std::to_string(r) +
                     (r < ranks.hosts.size() ? " (host " + ranks.hosts[r] + ")" : "");
    }
    if (run.sources() != nullptr) {
      print_banner(s, sc, *run.sources(), engine, served_by);
    } else {
      std::printf("rfsitl: scenario '%s', %zu node(s), no ports (--no-ports)\n", s.name.c_str(),
                  s.nodes.size());
    }
    if (ranks.distributed()) {
      std::fputs(session::describe_ranks(s, ranks).c_str(), stdout);
      std::fflush(stdout);
    }
    if (s.ip.enabled) print_ip_banner(run.ip_nodes());
  }
  if (const monitor::Dashboard* dashboard = run.dashboard()) {
    const bool drawn = run.dashboard_token_drawn();
    const char* control = !o.dashboard.control            ? "off; --dashboard-control allows it"
                          : run.dashboard_token().empty() ? "allowed"
                          : drawn ? "only with the control token of the URL below"
                                  : "only with the control token you gave";
    std::printf("rfsitl: dashboard %s (moving nodes %s)\n", dashboard->url().c_str(), control);
    if (drawn) {
      // Printed once: the dashboard is reachable beyond this machine, so the
      // token is what keeps others on the network from moving nodes.
      std::printf(
          "rfsitl: dashboard control URL (its token, drawn for this run, lets whoever has it move "
          "nodes; viewing needs none): %s?token=%s\n",
          dashboard->url().c_str(), run.dashboard_token().c_str());
    }
    std::fflush(stdout);
  }
  const std::string who =
      ranks.distributed() ? "rfsitl: rank " + std::to_string(ranks.rank) : "rfsitl";
  const external::ExternalRuntime* external = run.external();
  if (external && external->serves_any() && !wait_for_external_nodes(*external, s, signals, who)) {
    return false;
  }
  const std::size_t own_net_ports =
      s.nodes.size() - sc.external_net_ports.size() - sc.elsewhere.size();
  if (run.speaks() && o.ports) {
    std::printf(
        "rfsitl: ready, listening on %zu net port(s) and %zu location port(s)%s; %s\n",
        own_net_ports, s.nodes.size() - sc.elsewhere.size(),
        ranks.distributed() ? " on rank 0 (the others on theirs)" : "",
        s.timing.duration_s > 0 ? "stops after the duration or at Ctrl-C" : "Ctrl-C to stop");
  }
  if (s.timing.mode == scenario::TimeMode::kVirtual && run.speaks() && o.ports) {
    // Virtual time does not wait for the wall clock, so live agents cannot keep
    // up with it: their frames enter at whatever tick the engine has reached.
    std::printf(
        "rfsitl: virtual time runs as fast as the machine allows, not in step with the agents "
        "on the ports; the scenario's traffic: is what makes a run reproducible (%zu item(s))\n",
        s.traffic.size());
  }
  std::fflush(stdout);
  return true;
}

/// The traces' closing lines (every rank its own files).
void print_trace_lines(const session::SessionSummary& r) {
  if (!r.pcap.is_null()) {
    const std::string stopped = r.pcap["stopped"].get<bool>()
                                    ? "; stopped early: " + r.pcap["error"].get<std::string>()
                                    : "";
    std::printf("rfsitl: pcap trace %s: %llu frame events%s\n",
                r.pcap["path"].get<std::string>().c_str(),
                static_cast<unsigned long long>(r.pcap["events_written"].get<std::uint64_t>()),
                stopped.c_str());
  }
  if (!r.sigmf.is_null()) {
    for (const auto& n : r.sigmf["nodes"]) {
      if (n["stopped"].get<bool>()) {
        std::printf("rfsitl: SigMF recording %s stopped early: %s\n",
                    n["data"].get<std::string>().c_str(), n["error"].get<std::string>().c_str());
      }
    }
  }
}

/// --preflight: the scenario's first seconds in virtual time on this machine,
/// and whether real time will hold. Exit 0 when it holds, 1 when it does not.
int preflight_only(const session::Session& run) {
  if (!run.speaks()) return 0;
  try {
    const engine::PreflightReport r = engine::preflight(run.scenario());
    std::printf("rfsitl: preflight (%.2f virtual s in %.2f s): %s\n", r.virtual_s, r.wall_s,
                r.summary().c_str());
    return r.speed() >= 1.0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rfsitl run: --preflight: %s\n", e.what());
    return 2;
  }
}

/// Before a real-time run: a short preflight (a second of virtual time, at
/// most 1.5 s of wall time) and a warning when real time will not hold or
/// holds with little margin. Silent otherwise; --no-preflight skips it.
void warn_if_real_time_at_risk(const session::Session& run) {
  const scenario::Scenario& s = run.scenario();
  if (s.timing.mode != scenario::TimeMode::kRealTime || run.ranks().distributed()) return;
  try {
    const engine::PreflightReport r = engine::preflight(s, 1.0, 1.5);
    if (r.margin() < engine::kPreflightMinMargin) {
      std::printf("rfsitl: warning: %s (rfsitl run --preflight measures longer)\n",
                  r.summary().c_str());
    }
  } catch (const std::exception&) {
    // Whatever stops the engine from being built, the run's own steps report.
  }
}

/// The CLI around a Session: options from the flags, the steps, the signals,
/// and what is printed. Exit 2: nothing ran; 1: the run did not end well.
int run(const RunOptions& o) {
  session::SessionOptions options;
  try {
    options = session_options(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rfsitl run: %s\n", e.what());
    return 2;
  }
  session::Session run(std::move(options));
  try {
    run.build_scenario();
    run.place_ranks();
  } catch (const session::SessionError& e) {
    std::fprintf(stderr, "rfsitl run: %s\n", e.what());
    return 2;
  }
  if (o.preflight) return preflight_only(run);
  if (!o.no_preflight) warn_if_real_time_at_risk(run);
  // In a distributed run rank 0 speaks for the run: the banner, the stats,
  // the summary and its JSON, the dashboard. Its output file is opened now: a
  // path that cannot be written fails before the run, not after it with the
  // results lost.
  std::ofstream summary_out;
  if (!o.summary_json.empty() && run.speaks()) {
    summary_out.open(o.summary_json);
    if (!summary_out) {
      std::fprintf(stderr, "rfsitl run: --summary-json %s: cannot write: %s\n",
                   o.summary_json.c_str(), std::strerror(errno));
      return 2;
    }
  }
  // Signals are taken synchronously by this thread only; block them before the
  // ports' and the engine's threads exist so that every thread inherits the mask.
  const sigset_t signals = block_stop_signals();

  const double stats_every = run.scenario().engine.stats_interval_s;
  double next_stats = stats_every;
  session::ServeHooks hooks;
  hooks.ready = [&] { return announce(run, signals); };
  hooks.poll = [&] {
    const timespec poll{0, 50'000'000};
    const int sig = sigtimedwait(&signals, nullptr, &poll);
    if (sig == SIGINT || sig == SIGTERM) {
      std::printf("\nrfsitl: %s received, shutting down\n", sig == SIGINT ? "SIGINT" : "SIGTERM");
      return false;
    }
    if (stats_every > 0 && run.engine().status().wall_s >= next_stats) {
      if (run.speaks()) print_stats_line(run.engine());
      next_stats += stats_every;
    }
    return true;
  };
  session::ServeResult served;
  try {
    run.make_ports();
    run.make_ip();
    run.make_external();
    run.make_engine();
    run.add_observers();
    served = run.serve(hooks);
  } catch (const session::SessionError& e) {
    std::fprintf(stderr, "rfsitl run: %s\n", e.what());
    // Nothing ran: leave no empty summary behind to be mistaken for a run's
    // results (the session removes its trace).
    if (summary_out.is_open()) {
      summary_out.close();
      std::remove(o.summary_json.c_str());
    }
    return 2;
  }
  const session::RunRanks& ranks = run.ranks();
  switch (served.end) {
    case session::ServeEnd::kCompleted:
      break;
    case session::ServeEnd::kCancelled:
      print_summary(run.engine());
      return 1;
    case session::ServeEnd::kFailed:
      std::fprintf(stderr, "rfsitl run: rank %zu: %s\n", ranks.rank, served.error.c_str());
      [[fallthrough]];
    case session::ServeEnd::kPeersLost:
      // Open MPI does not survive a lost rank: leave without unwinding.
      print_partial_summary(run.engine(), ranks);
      std::_Exit(1);
  }
  const session::SessionSummary& r = run.finish();
  print_trace_lines(r);
  if (!run.speaks()) return 0;
  print_summary(run.engine());
  if (ranks.distributed()) {
    const scenario::Scenario& s = run.scenario();
    const double tick_s = s.timing.tick_samples / s.timing.sample_rate_hz;
    std::printf("distributed run, %zu ranks:\n%s", ranks.size,
                session::rank_summary(run.engine(), tick_s).c_str());
    std::fflush(stdout);
  }
  if (!r.external.is_null()) print_external_summary(r.external);
  if (summary_out.is_open()) {
    summary_out << monitor::json_text(r.document, 2) << "\n";
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
  CLI::Option* no_ports = cmd->add_flag(
      "--no-ports", opts->no_ports,
      "Open no net or location port: the scenario's traffic: is the only traffic, decoded frames "
      "are counted and dropped (campaigns, batch runs beside others)");
  for (auto& [source, value] : opts->source_flags) {
    static_cast<void>(value);
    cmd->get_option(source->flag.flag)->excludes(no_ports);
  }
  cmd->add_option("--set", opts->set,
                  "Set any scenario setting as the file would, e.g. --set mac.type=csma --set "
                  "channel.noise_power_db=-100 (repeatable; after the other flags)")
      ->type_name("KEY=VALUE")
      ->take_all()
      ->allow_extra_args(false);
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
  CLI::Option* preflight = cmd->add_flag(
      "--preflight", opts->preflight,
      "Run the scenario's first 2 s in virtual time, say whether real time will hold on this "
      "machine (cores needed, margin) and exit: 0 if it holds, 1 if not");
  cmd->add_flag("--no-preflight", opts->no_preflight,
                "Skip the one-second check before a real-time run (it warns when real time is at "
                "risk)")
      ->excludes(preflight);
  cmd->add_flag("--shared-noise", opts->shared_noise,
                "One noise source for all receivers (the paper's setup)");
  cmd->add_option("--summary-json", opts->summary_json,
                  "Write the final counters as JSON to this file (checked at start)")
      ->type_name("PATH");
  return [opts] { return run(*opts); };
}

}  // namespace rfsitl::app
