#pragma once
/// IP on every node: a network namespace per node holding a TAP interface, so
/// that unmodified IP software (ping, iperf3, a routing daemon, a ROS node) runs
/// in it and every packet it sends crosses the radio channel. Frames the
/// interface hands over go to the node's TX queue as FrameKind::kEthernet
/// frames (classified by ip/ethernet_frame.hpp: refused ones are counted as
/// ip_refused and logged); Ethernet frames the node's radio decodes are written
/// to its interface. Agent frames (kAgent) pass through to the net ports.
///
/// Namespaces are named <prefix>-<id>, the prefix "rfsitl-<net base>", so two
/// runs on different port bases never collide, and a run claims its prefix
/// (ip/run_registry.hpp): namespaces a killed run left behind are removed at the
/// next start with the same base, never those of a live run.
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rfsitl/engine/engine.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::agent_port {

/// One node's interface, as the banner and the summary show it.
struct IpNodeInfo {
  NodeId id = 0;
  std::string netns;        ///< the namespace's name (`ip netns exec NAME ...`)
  bool netns_owned = true;  ///< made by rfsitl (and removed at the end) or attached
  std::string interface;    ///< e.g. rf0
  std::string mac;          ///< 02:00:00:00:00:id
  std::string ipv4;         ///< e.g. 10.77.0.1/24
  std::string ipv6;         ///< e.g. fd72:6673:6974:1::1/64
  std::size_t mtu = 0;      ///< IP bytes per frame: the PHY's payload less framing
};

class IpPorts : public engine::FrameSink {
 public:
  /// The namespaces' prefix for a run on net port base `net_base`.
  static std::string prefix_for(std::uint16_t net_base) {
    return "rfsitl-" + std::to_string(net_base);
  }

  /// Makes (or attaches) every node's namespace and interface, sized to the
  /// engine's payload, and starts the thread that reads the interfaces. Throws
  /// std::runtime_error naming the node, namespace and step when one cannot be
  /// made; what was made until then is removed. Call once, before the run.
  virtual void start(engine::Engine& engine) = 0;

  /// Stops the reader and removes the interfaces and the namespaces rfsitl
  /// made (not attached ones). Idempotent; also done by the destructor.
  virtual void stop() = 0;

  /// After start(): the interface of every node this process serves
  /// (IpPlacement::here), in scenario order.
  virtual const std::vector<IpNodeInfo>& nodes() const = 0;

  /// Namespaces of a dead run with the same prefix, removed when this run
  /// claimed it.
  virtual const std::vector<std::string>& removed_stale() const = 0;

  /// {"prefix", "nodes": [IpNodeInfo...], "removed_stale": [...],
  ///  "frames_to_tap", "frames_from_tap"} for --summary-json.
  virtual nlohmann::json summary() const = 0;
};

/// Which nodes this process serves, and whether it claims the prefix. A run
/// in one process serves and claims everything; in a distributed run each rank
/// serves its own nodes and one rank per host claims, before any of them
/// starts (the claim sweeps every <prefix>-* namespace it finds).
struct IpPlacement {
  std::vector<bool> here;  ///< by node index; empty: every node
  bool claim = true;
};

/// One node's entry of IpPorts::summary()'s "nodes".
nlohmann::json ip_node_json(const IpNodeInfo& node);

/// Converts the JSON of IpPorts::summary()'s "nodes" back (a distributed
/// run's rank 0 gathers its peers' nodes this way). Throws nlohmann's
/// exceptions on JSON of another shape.
std::vector<IpNodeInfo> ip_nodes_from_json(const nlohmann::json& nodes);

/// Checks privileges and (placement.claim) claims the run's prefix, removing
/// a dead run's namespaces. Throws std::runtime_error with what is missing
/// and how to run it. `agents` receives every frame that is not an Ethernet
/// frame; it must outlive the returned object.
std::unique_ptr<IpPorts> make_ip_ports(const scenario::Scenario& scenario,
                                       engine::FrameSink& agents, IpPlacement placement = {});

}  // namespace rfsitl::agent_port
