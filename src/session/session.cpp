/// The Session's assembly steps, from the scenario to the observers; serve()
/// and finish() are in session_serve.cpp.
#include "rfsitl/session/session.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "rfsitl/io/bind_address.hpp"
#include "rfsitl/monitor/control_token.hpp"
#include "scenario_assembly.hpp"

namespace rfsitl::session {

const char* step_name(Step step) {
  switch (step) {
    case Step::kScenario:
      return "scenario";
    case Step::kPlacement:
      return "placement";
    case Step::kPorts:
      return "ports";
    case Step::kIp:
      return "ip";
    case Step::kExternal:
      return "external";
    case Step::kEngine:
      return "engine";
    case Step::kObservers:
      return "observers";
    case Step::kServe:
      return "serve";
    case Step::kFinish:
      return "finish";
    case Step::kDone:
      return "done";
  }
  return "?";
}

Session::Session(SessionOptions options) : options_(std::move(options)) {}

void Session::require_done(Step step) const {
  if (next_ > step) return;
  throw SessionStepError(std::string("session: what step '") + step_name(step) +
                         "' builds is not there yet (the step due is '" + step_name(next_) + "')");
}

void Session::run_step(Step step, bool collective, const std::function<void()>& body) {
  if (!refusal_.empty()) {
    throw SessionStepError(std::string("session: step '") + step_name(step) +
                           "' refused: " + refusal_);
  }
  if (next_ != step) {
    throw SessionStepError(std::string("session: step '") + step_name(step) +
                           "' called out of order: the step due is '" + step_name(next_) + "'");
  }
  std::string error;
  try {
    body();
  } catch (const std::exception& e) {
    error = e.what();
    if (error.empty()) error = "failed";
  }
  // Every rank does the step, or none does (in one process: its own verdict).
  // A collective step is also a barrier: what every rank did in it is done
  // before any rank goes on.
  std::optional<std::string> why;
  if (collective) {
    why = agree(ranks_, error);
  } else if (!error.empty()) {
    why = error;
  }
  if (why) {
    refusal_ = std::string("step '") + step_name(step) + "' failed";
    // Nothing ran: leave no trace file behind to be mistaken for a run's.
    if (pcap_) std::remove(pcap_path_.c_str());  // unlinked; the object closes it later
    throw SessionError(*why);
  }
  if (step != Step::kServe) next_ = static_cast<Step>(static_cast<int>(step) + 1);
}

void Session::build_scenario() {
  run_step(Step::kScenario, false, [this] { scenario_ = assemble_scenario(options_); });
}

void Session::place_ranks() {
  // start_ranks() shares its verdict itself: MPI is not up before it.
  run_step(Step::kPlacement, false, [this] {
    if (const auto why = start_ranks(scenario_, run_fingerprint(options_), ranks_)) {
      throw SessionError(*why);
    }
  });
}

void Session::make_ports() {
  run_step(Step::kPorts, true, [this] {
    if (options_.ports || options_.dashboard.enabled) {
      try {
        bind_address_ = io::resolve_bind_address(scenario_.ports.bind_address);
      } catch (const std::exception& e) {
        throw SessionError(std::string("ports.bind: ") + e.what());
      }
    }
    const scenario::Scenario& s = scenario_;
    ports_config_ = {bind_address_, s.ports.net_base, {}, {}};
    for (std::size_t i = 0; i < s.nodes.size(); ++i) {
      if (s.phy_of(i).external_program()) ports_config_.external_net_ports.push_back(s.nodes[i].id);
      if (!ranks_.here(i)) ports_config_.elsewhere.push_back(s.nodes[i].id);
    }
    if (!options_.ports) return;
    servers_ = agent_port::make_net_ports(ports_config_);
    sources_ =
        std::make_unique<LiveSources>(s, position::SourceContext{bind_address_, s.ports.loc_base},
                                      ranks_.here_mask(s.nodes.size()));
  });
}

void Session::make_ip() {
  // With IP, Ethernet frames go to the nodes' interfaces and the rest on to
  // the net ports. In a distributed run each rank serves its own nodes, one
  // rank per host claims the namespaces' prefix, and all agree on the claims
  // (a barrier) before any makes a namespace.
  run_step(Step::kIp, true, [this] {
    if (!scenario_.ip.enabled) return;
    engine::FrameSink& agents = servers_
                                    ? static_cast<engine::FrameSink&>(*servers_)
                                    : (options_.frames != nullptr ? *options_.frames : null_sink_);
    ip_ = agent_port::make_ip_ports(
        scenario_, agents, {ranks_.here_mask(scenario_.nodes.size()), ranks_.first_on_host()});
  });
}

void Session::make_external() {
  // A distributed run's ranks each serve their own external nodes, on a
  // socket of their own (rank_file_name: /tmp/rfsitl-<base>.rank<R>.sock).
  run_step(Step::kExternal, true, [this] {
    external_ = external::ExternalRuntime::create(
        scenario_, {ranks_.here_mask(scenario_.nodes.size()),
                    ranks_.distributed()
                        ? rank_file_name(external::external_socket_path(scenario_), ranks_.rank)
                        : std::string()});
  });
}

void Session::make_engine() {
  run_step(Step::kEngine, true, [this] {
    engine::FrameSink& sink = ip_        ? static_cast<engine::FrameSink&>(*ip_)
                              : servers_ ? static_cast<engine::FrameSink&>(*servers_)
                              : options_.frames != nullptr ? *options_.frames
                                                           : null_sink_;
    engine_ = engine::make_engine(
        scenario_, sink,
        external_ ? external_->transceiver_factory() : engine::TransceiverFactory{},
        ranks_.distribution());
  });
}

void Session::add_observers() {
  // Observers are added before any face opens: a frame an agent hands in
  // reaches every observer from the net ports' thread, and add_observer is
  // not thread-safe.
  run_step(Step::kObservers, true, [this] {
    const scenario::Scenario& s = scenario_;
    const SessionOptions& o = options_;
    // A distributed run's ranks each trace their own nodes, into files of their own.
    pcap_path_ = ranks_.distributed() ? rank_file_name(o.pcap.path, ranks_.rank) : o.pcap.path;
    if (!o.pcap.path.empty()) {
      pcap_ = monitor::make_pcap_trace(monitor::PcapTraceSettings{
          pcap_path_, o.pcap.max_file_bytes, o.pcap.files, s.timing.sample_rate_hz,
          10.0 * std::log10(std::max(s.channel.noise_variance, 1e-30))});
      engine_->add_observer(*pcap_);
    }
    if (!o.sigmf.directory.empty()) {
      monitor::SigmfSettings ss;
      ss.directory = o.sigmf.directory;
      ss.nodes = o.sigmf.nodes;
      if (ss.nodes.empty()) {
        for (const auto& n : s.nodes) ss.nodes.push_back(n.id);
      }
      // Another rank records its own nodes; an unknown id is the recorder's to refuse.
      std::erase_if(ss.nodes, [&](NodeId id) {
        const auto index = engine_->index_of(id);
        return index && !ranks_.here(*index);
      });
      ss.start_s = o.sigmf.start_s;
      ss.duration_s = o.sigmf.duration_s;
      ss.max_bytes = o.sigmf.max_bytes;
      sigmf_ = monitor::make_sigmf_recorder(ss, s);
      engine_->add_observer(*sigmf_);
    }
    control_token_ = o.dashboard.control_token;
    if (!control_token_.empty()) {
      if (const std::string why = monitor::control_token_problem(control_token_); !why.empty()) {
        throw SessionError("the dashboard's control token " + why);
      }
    } else if (o.dashboard.enabled && o.dashboard.control &&
               !monitor::bind_is_loopback(bind_address_)) {
      // Reachable beyond this machine: the token is what keeps others on the
      // network from moving nodes.
      control_token_ = monitor::generate_control_token();
      token_drawn_ = true;
    }
    // In a distributed run rank 0 serves the dashboard; the other ranks show
    // it what their nodes saw.
    if (o.dashboard.enabled && speaks()) {
      monitor::DashboardSettings ds;
      ds.bind_address = bind_address_;
      ds.port = o.dashboard.port.value_or(ds.port);
      ds.fall_back_to_any_port = !o.dashboard.port;
      ds.control = o.dashboard.control;
      ds.control_token = control_token_;
      if (sources_) ds.sources = sources_->status_fn();
      dashboard_ = monitor::start_dashboard(ds, s, *engine_);
    } else if (o.dashboard.enabled && ranks_.distributed()) {
      rank_view_ = std::make_unique<monitor::LiveView>(engine_->node_ids());
      engine_->add_observer(*rank_view_);
    }
  });
}

void Session::assemble() {
  build_scenario();
  place_ranks();
  make_ports();
  make_ip();
  make_external();
  make_engine();
  add_observers();
}

const scenario::Scenario& Session::scenario() const {
  require_done(Step::kScenario);
  return scenario_;
}

const RunRanks& Session::ranks() const {
  require_done(Step::kPlacement);
  return ranks_;
}

const std::string& Session::bind_address() const {
  require_done(Step::kPorts);
  return bind_address_;
}

const agent_port::NetPortsConfig& Session::net_ports_config() const {
  require_done(Step::kPorts);
  return ports_config_;
}

const LiveSources* Session::sources() const {
  require_done(Step::kPorts);
  return sources_.get();
}

const external::ExternalRuntime* Session::external() const {
  require_done(Step::kExternal);
  return external_.get();
}

engine::Engine& Session::engine() {
  require_done(Step::kEngine);
  return *engine_;
}

const monitor::Dashboard* Session::dashboard() const {
  require_done(Step::kObservers);
  return dashboard_.get();
}

const std::string& Session::dashboard_token() const {
  require_done(Step::kObservers);
  return control_token_;
}

const std::string& Session::pcap_path() const {
  require_done(Step::kObservers);
  return pcap_path_;
}

SessionSummary run_portless(scenario::Scenario scenario) {
  SessionOptions options;
  options.scenario = std::move(scenario);
  options.ports = false;
  Session session(std::move(options));
  session.assemble();
  session.serve();
  return session.finish();
}

}  // namespace rfsitl::session
