#pragma once
/// Where the emulator meets a vehicle's MAVLink stream, as a scenario or the
/// command line writes it:
///
///   tcp:HOST:PORT   the emulator connects to the vehicle (ArduPilot SITL serves
///                   SERIAL0 on 5760 + 10 i and SERIAL1 on 5762 + 10 i) and
///                   reconnects when the connection drops;
///   udp:HOST:PORT   the emulator listens there; the vehicle sends to it (PX4
///                   SITL, ArduPilot --out) and hears the emulator's replies.
///
/// A "+STEP" suffix spreads one endpoint over many nodes: node id n uses
/// PORT + STEP * (n - 1), so `tcp:127.0.0.1:5762+10` follows ArduPilot
/// instances 0, 1, 2 ... with nodes 1, 2, 3 ...
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "rfsitl/common/types.hpp"

namespace rfsitl::position {

enum class MavlinkTransport { kTcpClient, kUdpListen };

struct MavlinkEndpoint {
  MavlinkTransport transport = MavlinkTransport::kTcpClient;
  std::string host;        ///< name or address (IPv6 in brackets: [::1])
  std::uint16_t port = 0;  ///< 1..65535
  std::uint16_t step = 0;  ///< port increment per node id; 0: every node the same port

  /// The endpoint of node `id`: port + step * (id - 1). nullopt when that
  /// passes 65535.
  std::optional<MavlinkEndpoint> for_node(NodeId id) const;

  /// "tcp:127.0.0.1:5762" (with "+10" when step is set).
  std::string text() const;

  bool operator==(const MavlinkEndpoint&) const = default;
};

/// Parses an endpoint; on failure returns nullopt and sets `why` to a reason
/// that quotes the text ("expected tcp:HOST:PORT or udp:HOST:PORT[+STEP], got
/// 'tcp:5762'").
std::optional<MavlinkEndpoint> parse_mavlink_endpoint(std::string_view text, std::string& why);

}  // namespace rfsitl::position
