#pragma once
/// The handshake's JSON (wire_protocol.hpp): the hello a node's process sends
/// and the welcome the emulator answers, each written by one side and read by
/// the other. A reader trusts nothing it did not write: every number is
/// checked as a double against its range before it becomes an integer, so a
/// node_id of 4294967298 is refused instead of wrapping to node 2, and 1e30
/// never reaches a float-to-integer conversion (undefined behaviour).
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "rfsitl/common/types.hpp"

namespace rfsitl::external {

/// A hello or welcome that does not read. The message names the field and the
/// value as it was sent: "node_id 4294967298 out of range 1..254",
/// "tick_samples: expected an integer, got 2.5", "role: missing".
class HandshakeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What a process says when it connects.
struct Hello {
  NodeId node_id = 0;
  std::string role;                  ///< "samples" or "transceiver" (the hub checks it)
  std::string program = "external";  ///< for the emulator's log: client text, escape to print
  /// Claim the node only if no other process holds it: the emulator refuses
  /// the hello instead of dropping that process (the default, false, takes
  /// the node over, which is how a restarted process rejoins). Sent only when
  /// true, so older emulators, which ignore it, see the hello they knew.
  bool exclusive = false;
};

/// What the emulator tells a joining node.
struct Welcome {
  NodeId node_id = 0;
  double sample_rate_hz = 0.0;
  std::uint32_t tick_samples = 0;  ///< B
  bool virtual_time = false;
  std::string phy_json;  ///< transceiver role: the node's PHY settings as JSON; else empty
  /// Samples role: the TxReport version (tx_report.hpp) the emulator reads
  /// after a kTx's samples; 0 (an older emulator, or the field absent): send
  /// none.
  std::uint32_t tx_report = 0;
};

std::string hello_json(const Hello& hello);

/// Reads a hello: node_id an integer in 1..254, role a string, program a string
/// and exclusive a boolean if present. Throws HandshakeError.
Hello read_hello(const std::string& text);

/// The welcome with protocol kProtocolVersion; `phy_json` (if not empty) must
/// be a JSON object.
std::string welcome_json(const Welcome& welcome);

/// Reads a welcome: protocol kProtocolVersion, node_id in 1..254,
/// sample_rate_hz finite and > 0, tick_samples in 1..kMaxExternalTickSamples,
/// time_mode "realtime" or "virtual", phy an object and tx_report an integer
/// in 0..kMaxTxReportVersion if present. Throws HandshakeError.
Welcome read_welcome(const std::string& text);

/// What a process asks when it only wants to know which nodes are there
/// (kDiscover): nothing is claimed.
struct DiscoveryRequest {
  std::string program = "external";  ///< for the emulator's log: client text
};

/// One external node as kDiscovery describes it.
struct DiscoveredNode {
  NodeId node_id = 0;
  std::string label;               ///< for people: "<scenario> node <id>"
  std::string role;                ///< "samples" or "transceiver"
  double sample_rate_hz = 0.0;     ///< fs of the node's samples
  std::uint32_t tick_samples = 0;  ///< B
  double carrier_hz = 0.0;         ///< the scenario's radio carrier (baseband centre)
  bool virtual_time = false;
  bool claimed = false;  ///< a process is connected (or about to be) as this node
};

std::string discovery_request_json(const DiscoveryRequest& request);

/// Reads a discovery request: discovery kDiscoveryVersion, program a string if
/// present. Throws HandshakeError.
DiscoveryRequest read_discovery_request(const std::string& text);

/// The kDiscovery answer (version kDiscoveryVersion) listing `nodes`.
std::string discovery_json(const std::vector<DiscoveredNode>& nodes);

/// Reads a kDiscovery answer: discovery kDiscoveryVersion, nodes an array of
/// objects each checked like a welcome (node_id 1..254, sample_rate_hz finite
/// > 0, tick_samples 1..kMaxExternalTickSamples, time_mode, carrier_hz finite
/// > 0, role and label strings, claimed a boolean). Throws HandshakeError.
std::vector<DiscoveredNode> read_discovery(const std::string& text);

}  // namespace rfsitl::external
