#pragma once
/// The live dashboard: HTTP and WebSocket on one port, served by the emulator
/// itself with every asset built in (works without internet).
///
///   GET  /                  the page (map, link matrix, counters, spectrum, constellation)
///   GET  /api/stats         progress and counters as JSON
///   GET  /api/snapshot      the WebSocket snapshot message, once
///   GET  /metrics           Prometheus text format
///   POST /api/nodes/ID/position  {"x","y","z"} local metres or {"lat","lon","alt"}
///                           (only when control is on; 403 otherwise; with a control
///                           token, 401 unless the request carries it), within the
///                           location port's limits (rfsitl/common/position_limits.hpp)
///   GET  /ws                WebSocket: the server pushes {"type":"hello"} once, then
///                           {"type":"snapshot"} every push interval, {"type":"spectrum"}
///                           and {"type":"constellation"} for the node the viewer
///                           watches. The viewer sends {"type":"watch","node":ID} and
///                           {"type":"move","node":ID,"x":..,"y":..,"z":..}.
/// The message fields are in docs/dashboard.md. Every request must carry a Host
/// naming this server and, if it has an Origin, the dashboard's own
/// (request_checks.hpp): 421 or 403 otherwise. With a control token
/// (control_token.hpp) a viewer whose /ws upgrade did not carry it may watch
/// but not move nodes.
#include <cstdint>
#include <memory>
#include <string>

#include "rfsitl/engine/engine.hpp"
#include "rfsitl/monitor/live_view.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::monitor {

struct DashboardSettings {
  std::string bind_address = "127.0.0.1";
  std::uint16_t port = 15700;  ///< 0 = any free port
  /// When the port is taken and was not chosen by the user, take any free one.
  bool fall_back_to_any_port = true;
  bool control = false;  ///< viewers may move nodes
  /// Non-empty: control requests must carry this token (control_token.hpp);
  /// empty: control (if on) needs none.
  std::string control_token;
  double push_interval_s = 0.25;
  /// The live position sources' status per node (stats and snapshots show it).
  position::SourceStatusFn sources;
};

class Dashboard {
 public:
  virtual ~Dashboard() = default;  ///< stops the server and joins its thread
  virtual std::string url() const = 0;
  virtual std::uint16_t port() const = 0;
  /// Viewers connected now.
  virtual std::size_t viewers() const = 0;
  /// Messages not sent to viewers that did not keep up (a snapshot or spectrum
  /// replaced by a newer one, or the oldest dropped to bound the queue).
  virtual std::uint64_t messages_dropped() const = 0;
  /// The most messages any viewer's send queue has held (ViewerQueue::kCapacity
  /// at most, plus the hello).
  virtual std::size_t peak_send_queue() const = 0;
  /// Control requests (moves over HTTP or WebSocket) refused for want of the
  /// control token or with a wrong one.
  virtual std::uint64_t control_refused() const = 0;
};

/// Binds, registers its LiveView with `engine` (so call it before
/// Engine::run), and starts serving on its own thread. Throws
/// std::runtime_error naming the address and port when it cannot listen.
std::unique_ptr<Dashboard> start_dashboard(const DashboardSettings& settings,
                                           const scenario::Scenario& scenario,
                                           engine::Engine& engine);

}  // namespace rfsitl::monitor
