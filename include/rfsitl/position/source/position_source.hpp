#pragma once
/// A live position source: something outside the emulator that reports where
/// nodes are while the run goes on (the location port, an autopilot over
/// MAVLink). Mobility models are the other kind of source: pure functions
/// of virtual time that the engine evaluates itself (position/mobility/).
///
/// Exactly one source feeds a node. Reports go to a PositionSink; the sink
/// applies them at the engine's next tick.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rfsitl/common/position.hpp"
#include "rfsitl/common/types.hpp"
#include "rfsitl/config/component_info.hpp"
#include "rfsitl/position/source/node_state.hpp"

namespace rfsitl::position {

/// One report about one node; absent parts keep their last value.
struct StateReport {
  std::optional<Position> position;  ///< within common/position_limits.hpp
  std::optional<Velocity> velocity;  ///< local east/north/up, m/s
  std::optional<Attitude> attitude;
};

/// Where reports go. Implementations are thread-safe and return quickly (they
/// hand the report over; they never block on the engine).
class PositionSink {
 public:
  virtual ~PositionSink() = default;
  /// Node `index` (scenario order) is as `report` says, now.
  virtual void report(std::size_t index, const StateReport& report) = 0;
};

/// One node's source counters, as the summary and /api/stats show them.
struct SourceCounters {
  std::uint64_t updates = 0;     ///< positions accepted and passed on
  std::uint64_t errors = 0;      ///< input refused: corrupt frames, impossible coordinates
  std::uint64_t ignored = 0;     ///< valid input not used: no fix yet, another system
  std::uint64_t reconnects = 0;  ///< connections (or peers) after the first
  bool connected = false;        ///< a link to the node's vehicle is up now
  /// Wall seconds since the last accepted position; nullopt: none yet.
  std::optional<double> last_update_age_s;
  /// True when the source went silent for longer than its stale time after
  /// having reported: the node keeps its last position, drawn stale.
  bool stale = false;
  /// The source's own finer counts behind the ones above (e.g. "bad_crc",
  /// "no_fix"), in a fixed order, for the summary JSON.
  std::vector<std::pair<std::string, std::uint64_t>> detail;
};

class PositionSource {
 public:
  virtual ~PositionSource() = default;

  /// Opens what the source needs (sockets, its thread) and starts reporting to
  /// `sink`, which must outlive stop(). Throws std::runtime_error naming the
  /// node and endpoint that cannot be opened. Call once.
  virtual void start(PositionSink& sink) = 0;

  /// Stops reporting and joins the source's threads: after it returns the sink
  /// is never called again. Idempotent.
  virtual void stop() = 0;

  /// Thread-safe snapshot of node `index`'s counters; nullopt when this source
  /// does not feed that node.
  virtual std::optional<SourceCounters> counters(std::size_t index) const = 0;

  /// A few words naming where node `index`'s positions come from, for the banner
  /// ("tcp:127.0.0.1:5762, system 1"); "" when this source does not feed it.
  virtual std::string where(std::size_t index) const = 0;
};

/// What the monitor shows of a node's live source.
struct SourceStatus {
  std::string type;   ///< the registered name ("mavlink"), or "mobility"
  std::string where;  ///< PositionSource::where()
  SourceCounters counters;
  /// For a node fed by another source: the location port's counts, whose lines
  /// override that source's positions until its next report.
  std::optional<SourceCounters> overrides;
};

/// Node index -> its live source's status; nullopt for a node without one.
/// Thread-safe; may be empty (no live sources).
using SourceStatusFn = std::function<std::optional<SourceStatus>(std::size_t index)>;

/// A node given to a source: its index in the scenario, its id, and its settings
/// (validated against the component's declaration).
struct SourceNode {
  std::size_t index = 0;
  NodeId id = 1;
  config::Settings settings;
};

/// What the run gives every source besides its nodes.
struct SourceContext {
  std::string bind_address = "127.0.0.1";  ///< where sources that listen bind (--bind)
  /// The run's location-port base (ports.loc_base, --loc-base): node n's location
  /// port is base + 10 n unless its settings name one.
  std::uint16_t location_base = 15766;
};

/// A flag of `rfsitl run` that makes every node follow a source with one of
/// its settings given on the command line: `--mavlink ENDPOINT` is
/// `position: {source: mavlink, endpoint: ENDPOINT}` for the whole scenario.
struct SourceFlag {
  std::string flag;        ///< "--mavlink"; empty: the source has no flag
  std::string setting;     ///< the setting the flag's value sets ("endpoint")
  std::string value_name;  ///< what --help shows for the value ("ENDPOINT")
  std::string help;
};

/// What a live position source registers (registry/position_source_registry.hpp).
struct PositionSourceComponent {
  config::ComponentInfo info;  ///< kind "position"
  /// True when the source follows the wall clock (a live vehicle), so that a
  /// virtual-time run cannot use it.
  bool wall_clock = true;
  /// One source feeding all of `nodes`. Throws std::invalid_argument naming the
  /// node whose settings cannot work together (e.g. two nodes on one port).
  std::function<std::unique_ptr<PositionSource>(const SourceContext& context,
                                                const std::vector<SourceNode>& nodes)>
      make;
  SourceFlag flag;  ///< its shorthand on the command line, if any
};

}  // namespace rfsitl::position
