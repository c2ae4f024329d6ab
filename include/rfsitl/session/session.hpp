#pragma once
/// The composition root: one object that assembles a run in named steps
/// (session_step.hpp) and owns every part of it, so that `rfsitl run`, the
/// benchmarks and the Python module build a run the same way.
///
///   Session s(options);
///   s.assemble();            // scenario, placement, ports, ip, external, engine, observers
///   s.serve();               // opens the faces, runs the engine to its end
///   const SessionSummary& r = s.finish();
///
/// Each step may also be called on its own, in order, so that a caller can
/// act between two of them (the CLI opens its summary file after the
/// placement and prints its banner once the faces are open). A step out of
/// order throws SessionStepError; a step that fails throws SessionError and
/// the Session refuses every further step (destroying it is always safe).
///
/// In a distributed run (under mpirun) every step from "ports" on is
/// collective: every rank calls it, and every rank gets the same verdict.
///
/// Threads: one thread calls the steps and the accessors. While serve() runs,
/// other threads may call request_stop() and the engine's thread-safe views
/// (status(), counters()) through a reference taken from engine() before.
///
/// A run in one process may also go in parts instead of serve(), on the
/// caller's thread (the Python module's virtual-time runs):
///
///   s.assemble();
///   s.open();                // the faces, as serve() opens them
///   s.advance(1.0);          // to 1 s of virtual time; read, move, send...
///   s.advance(2.0);          // on to 2 s
///   s.finish();
#include <atomic>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "rfsitl/agent_port/ip_ports.hpp"
#include "rfsitl/agent_port/net_ports.hpp"
#include "rfsitl/engine/engine.hpp"
#include "rfsitl/external/external_runtime.hpp"
#include "rfsitl/monitor/dashboard.hpp"
#include "rfsitl/monitor/live_view.hpp"
#include "rfsitl/monitor/pcap_trace.hpp"
#include "rfsitl/monitor/sigmf_recorder.hpp"
#include "rfsitl/scenario/scenario.hpp"
#include "rfsitl/session/live_sources.hpp"
#include "rfsitl/session/run_ranks.hpp"
#include "rfsitl/session/session_options.hpp"
#include "rfsitl/session/session_step.hpp"
#include "rfsitl/session/session_summary.hpp"

namespace rfsitl::session {

/// What serve() calls back on its calling thread; both may be empty.
struct ServeHooks {
  /// Once every face is open, before the engine's first tick (the CLI prints
  /// its banner and waits for external nodes to join). False: end without
  /// running a tick (ServeEnd::kCancelled).
  std::function<bool()> ready;
  /// Called again and again while the engine runs; it paces the wait, so it
  /// should block for a short while (the CLI: sigtimedwait, 50 ms). False:
  /// stop the run at the next tick. Empty: wait for the end (or request_stop()).
  std::function<bool()> poll;
};

enum class ServeEnd {
  kCompleted,  ///< the scenario's duration was emulated, or the run was stopped
  kCancelled,  ///< ServeHooks::ready said no: no tick ran
  kFailed,     ///< the engine's run threw (a distributed run's exchange failed)
  /// A distributed run's other ranks did not stop with this one within 10 s
  /// (one died: Open MPI does not survive a lost rank). The engine's thread
  /// is stuck in an exchange: the caller reports what it can and ends the
  /// process (std::_Exit); the Session then leaks the parts that thread uses
  /// rather than destroy them under it.
  kPeersLost,
};

struct ServeResult {
  ServeEnd end = ServeEnd::kCompleted;
  std::string error;  ///< kFailed: why
};

class Session {
 public:
  /// Stores the options; nothing is built yet.
  explicit Session(SessionOptions options);
  /// Stops the run if it still goes on, closes every face, then destroys the
  /// parts in the reverse order of the members below.
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // ---- the steps, in order (Step) ----

  /// Reads the scenario file (or takes options.scenario, or places the
  /// default formation), applies the overrides and validates it.
  void build_scenario();
  /// Under mpirun: starts MPI, checks that every rank was given the same
  /// scenario and options, shares out the nodes. Otherwise every node is here.
  void place_ranks();
  /// Resolves ports.bind; makes the net ports and the live position sources
  /// (options.ports), which open in serve(). Collective.
  void make_ports();
  /// With ip.enabled: checks privileges and makes the nodes' namespaces and
  /// TAP interfaces. Nothing otherwise. Collective.
  void make_ip();
  /// Binds the external socket when this process serves an external node
  /// (a rank of a distributed run: a socket of its own). Collective.
  void make_external();
  /// Builds the engine and every transceiver. Collective.
  void make_engine();
  /// The pcap trace, the SigMF recording and the dashboard (rank 0's; the
  /// other ranks' live views), as the options ask. Collective.
  void add_observers();
  /// Every step above, in order.
  void assemble();

  /// Opens every face (position sources, net ports, TAP interfaces, the split
  /// architecture's children), gathers every rank's IP interfaces, calls
  /// hooks.ready, then runs the engine on a thread of its own until its
  /// duration, hooks.poll says stop, or request_stop(). Opening is
  /// collective and throws SessionError as a step does; the run's own end is
  /// the result.
  ServeResult serve(const ServeHooks& hooks = {});
  /// Opens every face as serve() does (hooks.ready is not asked) and runs no
  /// tick: the run then goes on by advance(), on the calling thread. Step
  /// "serve"; one process only (a distributed run's ticks are collective:
  /// SessionError).
  void open();
  /// After open(): runs the engine on the calling thread until `until_s`
  /// seconds of virtual time (the next tick boundary at or after it), the
  /// scenario's duration, or request_stop(); returns the time reached (s).
  /// May be called again and again; in real time it waits for the wall clock
  /// as serve() does. An engine that throws fails the Session (SessionError).
  double advance(double until_s);
  /// Stops the faces, finishes the traces, gathers the summary (collective:
  /// every rank's external nodes). Precondition: serve() ended kCompleted, or
  /// open() was called (however far advance() went).
  const SessionSummary& finish();

  /// Asks a running engine to stop at its next tick. Any thread; idempotent.
  void request_stop() { stop_.store(true); }

  /// The step due next (Step::kDone after finish()).
  Step next_step() const { return next_; }

  // ---- what the steps built; each throws SessionStepError before its step ----

  const SessionOptions& options() const { return options_; }
  const scenario::Scenario& scenario() const;  ///< after build_scenario()
  const RunRanks& ranks() const;               ///< after place_ranks()
  /// Whether this process speaks for the run (one process, or rank 0).
  bool speaks() const { return ranks_.rank == 0; }
  const std::string& bind_address() const;  ///< after make_ports(); "" without ports/dashboard
  /// Where the net ports are and which nodes have none here. After make_ports().
  const agent_port::NetPortsConfig& net_ports_config() const;
  const LiveSources* sources() const;                 ///< after make_ports(); null without ports
  const external::ExternalRuntime* external() const;  ///< after make_external(); null if none
  engine::Engine& engine();                           ///< after make_engine()
  const monitor::Dashboard* dashboard() const;        ///< after add_observers(); null if none
  /// The dashboard's control token ("" if none is needed), and whether it was
  /// drawn here rather than given. After add_observers().
  const std::string& dashboard_token() const;
  bool dashboard_token_drawn() const { return token_drawn_; }
  /// The pcap trace's path (a rank's own in a distributed run). After add_observers().
  const std::string& pcap_path() const;
  /// Every rank's IP interfaces in node order. During serve() from
  /// hooks.ready on; empty without IP.
  const std::vector<agent_port::IpNodeInfo>& ip_nodes() const { return ip_nodes_; }

 private:
  /// Runs step `step`'s `body`: refuses it out of order; turns its error into
  /// SessionError; in a distributed run (collective steps) agrees with the
  /// other ranks first.
  void run_step(Step step, bool collective, const std::function<void()>& body);
  void require_done(Step step) const;  // throws SessionStepError if `step` is not done
  void open_faces();                   // serve()'s and open()'s opening
  void close_faces();                  // stops everything that calls into the engine
  void engine_main();                  // the engine's thread

  SessionOptions options_;
  Step next_ = Step::kScenario;
  std::string refusal_;  // why every further step is refused (a step failed); "": none is

  // The members are destroyed bottom up. What must outlive what:
  //
  // - scenario_ is read by every part below (the engine and the external
  //   runtime keep references).
  // - ranks_ holds MPI: the engine exchanges through it, so it goes after
  //   the engine; MPI is finalized when it goes.
  // - null_sink_, servers_, ip_: the engine's sink (it holds a reference),
  //   so they outlive it; ip_ passes agents' frames on to servers_. Once
  //   open they also hand frames to the engine: close_faces() stops them (in
  //   finish() or the destructor) before anything is destroyed.
  // - external_: the proxies the engine holds talk through its hub.
  // - engine_: after everything it calls; before what calls it.
  // - pcap_, sigmf_: observers; the engine keeps pointers to them but calls
  //   them only while it runs, which ended before any member goes.
  // - sources_: reports into the engine; the dashboard reads their status,
  //   so they outlive it.
  // - dashboard_, rank_view_: read the engine (and the sources) from their
  //   own threads: first to go.
  // - the engine's thread is joined in the destructor's body, before all.
  scenario::Scenario scenario_;
  RunRanks ranks_;
  std::string bind_address_;
  agent_port::NetPortsConfig ports_config_;
  struct NullSink final : engine::FrameSink {
    void deliver(std::size_t, NetFrame&&) override {}
  } null_sink_;
  std::unique_ptr<agent_port::NetPorts> servers_;
  std::unique_ptr<agent_port::IpPorts> ip_;
  std::unique_ptr<external::ExternalRuntime> external_;
  std::unique_ptr<engine::Engine> engine_;
  std::string pcap_path_;
  std::unique_ptr<monitor::PcapTrace> pcap_;
  std::unique_ptr<monitor::SigmfRecorder> sigmf_;
  std::unique_ptr<LiveSources> sources_;
  std::string control_token_;
  bool token_drawn_ = false;
  std::unique_ptr<monitor::Dashboard> dashboard_;
  std::unique_ptr<monitor::LiveView> rank_view_;  // the other ranks' side of rank 0's dashboard

  std::vector<agent_port::IpNodeInfo> ip_nodes_;
  nlohmann::json ip_stale_ = nlohmann::json::array();
  std::optional<SessionSummary> summary_;

  std::atomic<bool> stop_{false};
  std::mutex end_mutex_;  // guards ended_, engine_error_ between the two threads
  std::condition_variable end_cv_;
  bool ended_ = false;        // the engine's run returned
  std::string engine_error_;  // what it threw
  bool stuck_ = false;        // ServeEnd::kPeersLost: the thread cannot be joined
  bool in_parts_ = false;     // open() was called: advance() drives the engine
  std::thread engine_thread_;
};

/// A whole run of `scenario` without ports, IP or observers, assemble() to
/// finish(): what benchmarks and tests need of a Session. Throws SessionError
/// as a step does.
SessionSummary run_portless(scenario::Scenario scenario);

}  // namespace rfsitl::session
