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

/// Which external nodes this process serves and where it listens. A run in
/// one process serves them all on external_socket_path(s); a rank of a
/// distributed run serves its own on a socket of its own.
struct ExternalPlacement {
  std::vector<bool> here;   ///< by node index; empty: every node
  std::string socket_path;  ///< empty: external_socket_path(s)
};

class ExternalRuntime {
 public:
  /// Binds the external socket when this process serves an external node.
  /// Returns nullptr when no node of the scenario runs externally. Throws
  /// std::runtime_error (socket in use, path too long).
  static std::unique_ptr<ExternalRuntime> create(const scenario::Scenario& s,
                                                 ExternalPlacement placement = {});

  /// Whether this process serves an external node (and has a socket).
  bool serves_any() const { return hub_ != nullptr; }

  /// Builds proxies for the external nodes served here, built-in PHYs for the
  /// others, and for external nodes served elsewhere stand-ins with their
  /// figures (payload, sensitivity, latency) that process no samples.
  engine::TransceiverFactory transceiver_factory() const;

  /// Starts the `rfsitl node` children (process: child). Throws std::runtime_error.
  void start_children();

  /// Preconditions (both): serves_any().
  const std::string& socket_path() const { return hub_->socket_path(); }
  const ExternalHub& hub() const { return *hub_; }
  std::uint64_t child_restarts() const { return children_ ? children_->restarts() : 0; }

  /// Per external node served here: role, joins, drops, timeouts (for the
  /// summary); "socket" is null when none is.
  nlohmann::json summary() const;

 private:
  ExternalRuntime(const scenario::Scenario& s, const ExternalPlacement& placement);

  scenario::Scenario scenario_;
  std::vector<ExternalNodeSpec> specs_;
  std::unique_ptr<ExternalHub> hub_;
  std::unique_ptr<ChildSupervisor> children_;
};

}  // namespace rfsitl::external
