#pragma once
/// The MAVLink position source: follows one vehicle per node (an ArduPilot or
/// PX4 SITL instance, or a real autopilot) over TCP or UDP, one VehicleLink per
/// node, all on one I/O thread. Runs on the wall clock: a run that uses it is a
/// real-time run.
///
/// Scenario:   position: {source: mavlink, endpoint: "tcp:127.0.0.1:5762+10", rate_hz: 10}
/// Command:    rfsitl run SCENARIO --mavlink tcp:127.0.0.1:5762+10
#include <memory>
#include <string>
#include <vector>

#include "rfsitl/config/fields.hpp"
#include "rfsitl/position/mavlink_source/mavlink_endpoint.hpp"
#include "rfsitl/position/source/position_source.hpp"

namespace rfsitl::position {

/// A node's settings, declared once (mavlink_source_settings()).
struct MavlinkSourceSettings {
  std::string endpoint;  ///< MavlinkEndpoint text, "+STEP" allowed
  double rate_hz = 10.0;
  std::uint64_t sysid = 0;     ///< 0: the first vehicle heard
  double stale_after_s = 3.0;  ///< silence after which the node is shown stale
};

const config::Fields<MavlinkSourceSettings>& mavlink_source_settings();

/// Reconnection pauses of a TCP endpoint: first, doubling up to the cap.
inline constexpr double kMavlinkReconnectFirstS = 0.25;
inline constexpr double kMavlinkReconnectMaxS = 4.0;

/// Builds the source for `nodes` (settings validated). Throws
/// std::invalid_argument naming the node when an endpoint's port with its step
/// passes 65535 or two nodes name the same endpoint.
std::unique_ptr<PositionSource> make_mavlink_source(const std::vector<SourceNode>& nodes);

}  // namespace rfsitl::position
