#pragma once
/// A run in virtual time that a Python caller drives step by step: assembled
/// by the same Session as `rfsitl run` (without ports: the caller is every
/// node's agent), then advanced, read and acted on between steps. Plain C++;
/// the bindings (module.cpp) only convert.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rfsitl/engine/node_counters.hpp"
#include "rfsitl/monitor/link_table.hpp"
#include "rfsitl/phy/per_curve.hpp"
#include "rfsitl/position/source/position_source.hpp"
#include "rfsitl/scenario/scenario.hpp"
#include "rfsitl/session/session.hpp"
#include "run_log.hpp"

namespace rfsitl::python {

struct VirtualRunOptions {
  /// Decoded frames are the caller's (it reads them as "received" events);
  /// false: they count as to_agent_dropped, as in `rfsitl run` with no agent
  /// connected (so that both give the same counters).
  bool keep_frames = true;
  bool record_events = true;
  /// Nodes' samples may be tapped (set_tap). Without this and record_events
  /// nothing watches the engine: the run costs what `rfsitl run` costs.
  bool taps = true;
  std::size_t max_events = 1'000'000;
  std::size_t max_tap_samples = std::size_t{1} << 24;
  std::string pcap_path;  ///< "": no trace
  std::string sigmf_dir;  ///< "": no recording
};

class VirtualRun {
 public:
  /// Assembles the run (time.mode forced to virtual) and opens it at time 0.
  /// Throws session::SessionError (the scenario's or a step's error).
  VirtualRun(scenario::Scenario scenario, const VirtualRunOptions& options);
  ~VirtualRun();

  const scenario::Scenario& scenario() const { return session_->scenario(); }
  const std::vector<NodeId>& node_ids() const { return engine_->node_ids(); }
  /// Node `id`'s index; std::out_of_range naming the run's nodes if none.
  std::size_t index_of(NodeId id) const;

  double now_s() const;
  double tick_s() const;
  /// The scenario's duration (0: none): advance() stops there.
  double end_s() const;

  /// Runs to `until_s` of virtual time (the next tick boundary); returns the
  /// time reached. The taps then hold this step's samples. Releasing the GIL
  /// is the caller's.
  double advance(double until_s);

  /// Hands `payload` from node `src` to its TX queue for `dst` (255 or the
  /// broadcast id: everyone). False when the queue is full (counted as
  /// queue_dropped). std::invalid_argument when larger than the node's MTU.
  bool send(NodeId src, NodeId dst, std::vector<std::uint8_t> payload);
  /// Moves node `id` (and sets its velocity, attitude) from the next tick.
  void report(NodeId id, const position::StateReport& report);

  std::vector<engine::NodeCountersSnapshot> counters();
  std::vector<monitor::LinkRow> links(std::size_t payload_bytes) const;
  std::vector<std::optional<Ecef>> positions() const { return engine_->positions(); }

  std::vector<engine::FrameEvent> take_events() { return log_->take_events(); }
  std::uint64_t events_dropped() const { return log_->events_dropped(); }
  /// std::logic_error unless the options allowed taps.
  void set_tap(NodeId id, bool on);
  /// Node `id`'s samples of the latest step (moved out: a second call gives
  /// none), and the virtual sample time of the first.
  TapBuffer take_samples(NodeId id);

  /// Ends the run (no further step) and returns the summary document, the
  /// same as `rfsitl run --summary-json` writes. Idempotent.
  const nlohmann::json& finish();
  bool finished() const { return summary_ != nullptr; }

 private:
  void require_open() const;

  struct Agents;  // the engine's frame sink: the caller's side of every node
  std::unique_ptr<Agents> agents_;
  std::unique_ptr<session::Session> session_;
  engine::Engine* engine_ = nullptr;
  std::unique_ptr<RunLog> log_;  // the engine's observer only with events or taps
  bool taps_ = false;
  std::vector<phy::PerCurve> curves_;
  const nlohmann::json* summary_ = nullptr;
};

}  // namespace rfsitl::python
