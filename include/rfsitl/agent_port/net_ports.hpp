#pragma once
/// The agents' TCP face of the emulator: for every node a net port (UB-ANC
/// framing, io/net_framing.hpp) where its agent hands in frames and receives the
/// frames its radio decoded, all served by one I/O thread. (Positions come in
/// through position sources, position/; the location port is one of them.)
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rfsitl/engine/engine.hpp"
#include "rfsitl/io/port_error.hpp"

namespace rfsitl::agent_port {

struct NetPortsConfig {
  std::string bind_address = "127.0.0.1";
  std::uint16_t net_base = 15763;
  /// Nodes whose net port another program serves (external transceivers that
  /// own their net port): no net port is opened for them here.
  std::vector<NodeId> external_net_ports;
  /// Nodes another rank of a distributed run serves: no net port here either.
  std::vector<NodeId> elsewhere;
};

/// Owns the listening sockets and the I/O thread. Frames decoded by the engine
/// reach it through the FrameSink interface (called on the engine thread).
class NetPorts : public engine::FrameSink {
 public:
  /// Net port of node id n: net_base + 10 n.
  static std::uint16_t net_port(const NetPortsConfig& c, NodeId id) {
    return static_cast<std::uint16_t>(c.net_base + 10 * id);
  }

  /// Binds every port now (all are listening when this returns) and starts the
  /// I/O thread. Throws io::PortError if any port cannot be bound. Frames the
  /// engine delivers before start() are counted as to_agent_dropped.
  virtual void start(engine::Engine& engine) = 0;

  /// Closes all sockets and joins the I/O thread. Idempotent.
  virtual void stop() = 0;
};

std::unique_ptr<NetPorts> make_net_ports(const NetPortsConfig& config);

}  // namespace rfsitl::agent_port
