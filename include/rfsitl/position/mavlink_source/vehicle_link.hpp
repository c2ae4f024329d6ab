#pragma once
/// The emulator's side of one MAVLink conversation with one vehicle, without
/// any I/O: bytes in, position reports and bytes to send out, on a clock the
/// caller supplies (wall seconds). MavlinkSource runs one per node over a TCP
/// connection or a UDP peer; tests drive it directly.
///
/// What it does:
///  - sends a HEARTBEAT every second as an onboard component (MAV_COMP_ID
///    ONBOARD_COMPUTER, 191) of the vehicle's system; autopilots stream only
///    on links they hear from;
///  - picks the vehicle: the configured system id, or else the first system
///    whose autopilot component (1) sends a HEARTBEAT naming an autopilot or a
///    GLOBAL_POSITION_INT; everything from other systems and other components
///    is ignored (counted);
///  - asks for GLOBAL_POSITION_INT and ATTITUDE at the configured rate with
///    MAV_CMD_SET_MESSAGE_INTERVAL; if the vehicle refuses it (COMMAND_ACK not
///    ACCEPTED), or no position arrives within kRequestRetryS, it also sends
///    REQUEST_DATA_STREAM (POSITION and EXTRA1) and asks again every
///    kRequestRetryS until positions flow; the same after every reconnect;
///  - reports positions from GLOBAL_POSITION_INT (lat, lon, alt above mean sea
///    level taken as the altitude), its velocity (NED -> local east/north/up)
///    and ATTITUDE. A report with latitude = longitude = 0 is the autopilot
///    saying it has no position yet (ArduPilot SITL sends these for its first
///    seconds): it is counted as no_fix and not passed on, so the node keeps its
///    scenario position (or stays unknown) until the vehicle has a fix.
/// Not thread-safe: one thread drives a link.
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "rfsitl/position/mavlink/encoder.hpp"
#include "rfsitl/position/mavlink/parser.hpp"
#include "rfsitl/position/source/position_source.hpp"

namespace rfsitl::position {

struct VehicleLinkSettings {
  double rate_hz = 10.0;   ///< GLOBAL_POSITION_INT and ATTITUDE per second, asked of the vehicle
  std::uint8_t sysid = 0;  ///< the vehicle's system id; 0: the first vehicle heard
  std::uint8_t own_compid = 191;  ///< MAV_COMP_ID_ONBOARD_COMPUTER
};

/// Everything a link counts. Monotonic for the whole run (across reconnects).
struct VehicleLinkCounters {
  std::uint64_t positions = 0;        ///< GLOBAL_POSITION_INT passed on
  std::uint64_t attitudes = 0;        ///< ATTITUDE passed on
  std::uint64_t no_fix = 0;           ///< GLOBAL_POSITION_INT with lat = lon = 0, not passed on
  std::uint64_t bad_coordinates = 0;  ///< positions outside the limits, not passed on
  std::uint64_t other_system = 0;     ///< messages from a system other than the vehicle's
  std::uint64_t other_component = 0;  ///< messages from the vehicle's other components
  std::uint64_t heartbeats_sent = 0;
  std::uint64_t interval_requests = 0;  ///< SET_MESSAGE_INTERVAL commands sent
  std::uint64_t stream_requests = 0;    ///< REQUEST_DATA_STREAM messages sent
  std::uint64_t interval_refused = 0;   ///< COMMAND_ACKs that refused SET_MESSAGE_INTERVAL
  std::uint64_t connections = 0;        ///< connected() calls
  mavlink::ParserCounters parser;       ///< frames and bytes, with the corrupt ones
};

class VehicleLink {
 public:
  /// Seconds without a position after a request before asking again.
  static constexpr double kRequestRetryS = 2.0;
  static constexpr double kHeartbeatPeriodS = 1.0;

  /// `log` hears every problem worth a line (bad checksum, foreign system,
  /// impossible coordinate...), already rate-limited per reason: the first of
  /// each kind, then at 10, 100, 1000 ... of it. `info` hears what happens in
  /// the normal case (which system it follows). Either may be empty.
  explicit VehicleLink(VehicleLinkSettings settings,
                       std::function<void(const std::string&)> log = {},
                       std::function<void(const std::string&)> info = {});

  /// A connection (or a new UDP peer) is up: a partial frame from before is
  /// dropped, and the vehicle is greeted and asked for its stream again.
  void connected(double now_s);

  /// Consumes bytes from the vehicle; appends what to pass on to `out`.
  void receive(std::span<const std::uint8_t> bytes, double now_s, std::vector<StateReport>& out);

  /// Appends the frames due at `now_s` (heartbeat, requests) to `out`.
  void poll(double now_s, std::vector<std::uint8_t>& out);

  /// The vehicle's system id once known.
  std::optional<std::uint8_t> vehicle() const { return vehicle_; }
  /// Wall time of the last position passed on; nullopt: none yet.
  std::optional<double> last_position_s() const { return last_position_s_; }

  /// Counters; parser counters included.
  VehicleLinkCounters counters() const;

 private:
  void handle(const mavlink::MavlinkMessage& m, double now_s, std::vector<StateReport>& out);
  bool from_vehicle(const mavlink::FrameInfo& f, const mavlink::MessagePayload& p);
  void take_position(const mavlink::GlobalPositionInt& g, double now_s,
                     std::vector<StateReport>& out);
  void request_streams(double now_s, bool legacy_too, std::vector<std::uint8_t>& out);
  // Logs `what` when a count crosses 1, 10, 100, ...
  void note(std::uint64_t before, std::uint64_t after, const std::string& what);

  VehicleLinkSettings settings_;
  std::function<void(const std::string&)> log_;
  std::function<void(const std::string&)> info_;
  mavlink::MavlinkParser parser_;
  mavlink::MavlinkEncoder encoder_;
  std::vector<mavlink::MavlinkMessage> messages_;
  std::optional<std::uint8_t> vehicle_;
  bool up_ = false;
  double next_heartbeat_s_ = 0.0;
  std::optional<double> last_request_s_;
  std::optional<double> last_stream_s_;  // any GLOBAL_POSITION_INT, fix or not
  std::optional<double> last_position_s_;
  bool asked_ = false;          // requested on this connection
  bool force_request_ = false;  // ask now (after a refusal)
  bool legacy_ = false;         // the vehicle refused SET_MESSAGE_INTERVAL
  mavlink::MavlinkVersion version_ = mavlink::MavlinkVersion::kV2;  // the vehicle's
  VehicleLinkCounters counters_;
};

}  // namespace rfsitl::position
