#pragma once
/// The process side of role "transceiver" (`rfsitl node`): joins the emulator,
/// builds the PHY the welcome names, and answers the engine's forwarded calls
/// until the emulator closes the connection.
#include <atomic>
#include <string>

#include "rfsitl/common/types.hpp"

namespace rfsitl::external {

struct TransceiverNodeOptions {
  std::string socket_path;
  NodeId node_id = 0;
  double connect_timeout_s = 10.0;  ///< keep retrying while the emulator starts up
  /// Pause after the first failed attempt to join; it doubles after each
  /// further failure up to retry_max_s, so that a process the emulator refuses
  /// (wrong role, unknown node) does not flood it with hellos.
  double retry_first_s = 0.05;
  double retry_max_s = 2.0;
};

/// Joins (retrying with backoff until the connect timeout; each distinct
/// reason the emulator gives for refusing the node is printed on stderr once),
/// then serves the emulator. Returns 0 when the emulator ended the run (closed
/// the connection) or `stop` was set, 1 on a protocol or PHY error (message on
/// stderr). Throws std::runtime_error if it cannot join within the connect
/// timeout (ConnectRejected if the last attempt was refused).
int run_transceiver_node(const TransceiverNodeOptions& options, const std::atomic<bool>& stop);

}  // namespace rfsitl::external
