#pragma once
/// The split architecture's process keeper: starts one `rfsitl node` process
/// per node that the scenario runs as a child, and restarts one that dies so
/// that its node rejoins (each exit is logged with its status).
#include <memory>
#include <string>
#include <vector>

#include "rfsitl/common/types.hpp"

namespace rfsitl::external {

struct ChildSettings {
  std::string executable;  ///< the rfsitl binary (normally /proc/self/exe)
  std::string socket_path;
  std::vector<NodeId> node_ids;
  double restart_delay_s = 0.5;  ///< pause before restarting a process that died
  bool restart = true;
};

class ChildSupervisor {
 public:
  virtual ~ChildSupervisor() = default;  ///< terminates the children (SIGTERM, then SIGKILL)

  /// Current process id of node `id`'s child; 0 while it is not running.
  virtual int pid_of(NodeId id) const = 0;

  /// Children that died and were started again.
  virtual std::uint64_t restarts() const = 0;
};

/// Starts every child now. Throws std::runtime_error if one cannot be spawned.
std::unique_ptr<ChildSupervisor> start_children_of(const ChildSettings& settings);

/// Path of the running executable, for ChildSettings::executable.
std::string current_executable();

}  // namespace rfsitl::external
