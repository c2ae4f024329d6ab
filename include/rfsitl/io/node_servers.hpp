#pragma once
/// The TCP face of the emulator: for every node a net port (UB-ANC framing) and
/// a location port (one position per line), all served by one I/O thread.
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "rfsitl/common/position.hpp"
#include "rfsitl/engine/engine.hpp"

namespace rfsitl::io {

/// A port could not be opened. what() names the node, the port's role and number,
/// and the system's reason (e.g. "net port 15773 of node 1: Address already in use").
class PortError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ServerConfig {
  std::string bind_address = "127.0.0.1";
  std::uint16_t net_base = 15763;
  std::uint16_t loc_base = 15766;
  GeodeticPosition origin;  ///< for local x/y/z positions
  /// Nodes whose net port another program serves (external transceivers that
  /// own their net port): no net port is opened for them here.
  std::vector<NodeId> external_net_ports;
};

/// Owns the listening sockets and the I/O thread. Frames decoded by the engine
/// reach it through the FrameSink interface (called on the engine thread).
class NodeServers : public engine::FrameSink {
 public:
  /// Net port of node id n: net_base + 10 n; location port: loc_base + 10 n.
  static std::uint16_t net_port(const ServerConfig& c, NodeId id) {
    return static_cast<std::uint16_t>(c.net_base + 10 * id);
  }
  static std::uint16_t loc_port(const ServerConfig& c, NodeId id) {
    return static_cast<std::uint16_t>(c.loc_base + 10 * id);
  }

  /// Binds every port now (all are listening when this returns) and starts the
  /// I/O thread. Throws PortError if any port cannot be bound. Frames the engine
  /// delivers before start() are counted as to_agent_dropped.
  virtual void start(engine::Engine& engine) = 0;

  /// Closes all sockets and joins the I/O thread. Idempotent.
  virtual void stop() = 0;
};

std::unique_ptr<NodeServers> make_node_servers(const ServerConfig& config);

}  // namespace rfsitl::io
