#pragma once
/// Everything a run needs for nodes whose transceiver is another process: the
/// hub on the external socket, the `rfsitl node` children of the split
/// architecture, and the engine's transceiver factory that puts proxies in
/// their place.
#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rfsitl/engine/engine.hpp"
#include "rfsitl/external/child_supervisor.hpp"
#include "rfsitl/external/external_hub.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::external {

/// The socket path a scenario uses: external.socket, else /tmp/rfsitl-<net_base>.sock.
std::string external_socket_path(const scenario::Scenario& s);

class ExternalRuntime {
 public:
  /// Binds the external socket. Returns nullptr when no node runs externally.
  /// Throws std::runtime_error (socket in use, path too long).
  static std::unique_ptr<ExternalRuntime> create(const scenario::Scenario& s);

  /// Builds proxies for the external nodes, built-in PHYs for the others.
  engine::TransceiverFactory transceiver_factory() const;

  /// Starts the `rfsitl node` children (process: child). Throws std::runtime_error.
  void start_children();

  const std::string& socket_path() const { return hub_->socket_path(); }
  const ExternalHub& hub() const { return *hub_; }
  std::uint64_t child_restarts() const { return children_ ? children_->restarts() : 0; }

  /// Per external node: role, joins, drops, timeouts (for the summary).
  nlohmann::json summary() const;

 private:
  explicit ExternalRuntime(const scenario::Scenario& s);

  scenario::Scenario scenario_;
  std::vector<ExternalNodeSpec> specs_;
  std::unique_ptr<ExternalHub> hub_;
  std::unique_ptr<ChildSupervisor> children_;
};

}  // namespace rfsitl::external
