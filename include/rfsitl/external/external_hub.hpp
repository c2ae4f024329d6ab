#pragma once
/// The emulator's end of the external-transceiver socket: listens on one Unix
/// socket path, admits each connecting process as the node its hello names
/// (checking that the scenario declares that node external and the role fits),
/// and keeps one NodeLink per external node for the engine.
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rfsitl/external/node_link.hpp"

namespace rfsitl::external {

/// How a node's process talks to the emulator.
enum class Role {
  kSamples,      ///< owns its net port; exchanges samples only (GNU Radio blocks)
  kTransceiver,  ///< runs a built-in PHY for the emulator (`rfsitl node`)
};

const char* role_name(Role role);

struct ExternalNodeSpec {
  std::size_t index = 0;  ///< engine index
  NodeId id = 0;
  Role role = Role::kSamples;
  std::string phy_json;  ///< transceiver role: PHY settings sent in the welcome
};

struct HubSettings {
  std::string socket_path;
  int reply_timeout_ms = 1000;
  /// A connection must say hello within this, counted from its own accept:
  /// hellos are awaited side by side, so silent connections never delay others.
  int hello_timeout_ms = 2000;
  double sample_rate_hz = 1e6;
  std::uint32_t tick_samples = 250;
  bool virtual_time = false;
  double carrier_hz = 2.4e9;  ///< told in discovery answers (the radio's carrier)
  /// Discovery labels nodes "<scenario_name> node <id>".
  std::string scenario_name = "rfsitl";
};

class ExternalHub {
 public:
  virtual ~ExternalHub() = default;

  virtual const std::string& socket_path() const = 0;

  /// The link of engine node `index`; nullptr if that node is not external.
  virtual std::shared_ptr<NodeLink> link(std::size_t index) const = 0;

  /// Ids of the external nodes that have not connected yet, not even once.
  virtual std::vector<NodeId> never_joined() const = 0;

  /// Hellos and discovery requests refused so far (unknown node, wrong role,
  /// bad message).
  virtual std::uint64_t rejected() const = 0;
};

/// Binds `settings.socket_path` (a stale socket file left by a dead emulator is
/// replaced; one that a live emulator answers on is not) with mode 0600 and
/// starts the accept thread, which also waits for the hellos of up to
/// kMaxWaitingHellos connections at a time (beyond that, the one waiting
/// longest is refused). Throws std::runtime_error naming the path.
inline constexpr std::size_t kMaxWaitingHellos = 64;

std::unique_ptr<ExternalHub> make_external_hub(const HubSettings& settings,
                                               const std::vector<ExternalNodeSpec>& nodes);

}  // namespace rfsitl::external
