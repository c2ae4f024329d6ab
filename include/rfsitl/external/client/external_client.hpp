#pragma once
/// The external side of a node: what a GNU Radio block, an `rfsitl node`
/// process or any other program uses to join an emulator run (protocol in
/// wire_protocol.hpp).
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "rfsitl/common/types.hpp"
#include "rfsitl/external/client/handshake.hpp"
#include "rfsitl/external/client/message_channel.hpp"
#include "rfsitl/external/client/tx_report.hpp"

namespace rfsitl::external {

/// One tick as the samples role sees it.
struct Tick {
  std::uint64_t index = 0;       ///< k
  std::uint64_t time = 0;        ///< virtual sample index of tick k's first sample
  std::span<const cf32> rx;      ///< samples received during tick k-1 (valid until next wait)
  bool follows_previous = true;  ///< false when ticks were missed since the last one
};

/// Thrown by ExternalClient::connect() when the emulator answered the hello
/// with kReject: retrying is pointless until the configuration changes.
class ConnectRejected : public std::runtime_error {
 public:
  ConnectRejected(const std::string& what, std::string reason)
      : std::runtime_error(what), reason_(std::move(reason)) {}
  /// The emulator's kReject text alone.
  const std::string& reason() const { return reason_; }

 private:
  std::string reason_;
};

/// Asks the emulator listening on `socket_path` which external nodes it has
/// (kDiscover), claiming none of them; waits up to `timeout_ms` for the
/// answer. Throws std::runtime_error naming the socket and the reason (no
/// emulator listening, timeout, refused, bad answer).
std::vector<DiscoveredNode> discover(const std::string& socket_path, int timeout_ms,
                                     const std::string& program = "external");

class ExternalClient {
 public:
  struct Settings {
    std::string socket_path;
    NodeId node_id = 0;
    std::string role = "samples";  ///< "samples" or "transceiver"
    std::string program = "external";
    int handshake_timeout_ms = 5000;
    /// Hello::exclusive: refused while another process holds the node,
    /// instead of taking it over.
    bool exclusive = false;
  };

  explicit ExternalClient(Settings settings) : settings_(std::move(settings)) {}

  /// Connects and handshakes. Throws ConnectRejected when the emulator refuses
  /// the hello, else std::runtime_error naming the socket and the reason (no
  /// emulator listening, timeout, bad welcome).
  const Welcome& connect();
  bool connected() const { return channel_.is_open(); }
  const Welcome& welcome() const { return welcome_; }
  void disconnect() { channel_.close(); }

  /// Samples role: waits up to `timeout_ms` for the next tick. On kOk, tick()
  /// is valid and the caller must answer with send_tx() before the emulator's
  /// timeout. kClosed: the emulator went away or dropped this node; kMalformed:
  /// an unexpected message (the connection is closed). Connect again after either.
  RecvStatus wait_tick(int timeout_ms);
  const Tick& tick() const { return tick_; }

  /// Samples role: answers the current tick with `tx` (at most B samples; the
  /// emulator zero-pads fewer). Throws std::invalid_argument if tx.size() > B.
  bool send_tx(std::span<const cf32> tx);
  /// The same, with `report` after the samples when the emulator's welcome
  /// asks for one (Welcome::tx_report >= 1); without, when it does not.
  bool send_tx(std::span<const cf32> tx, const TxReport& report);

  /// Ticks that did not follow the previous one seen, across reconnections:
  /// the emulator dropped this node in between (or a protocol slip).
  std::uint64_t discontinuities() const { return discontinuities_; }

  /// Raw access for the transceiver role.
  MessageChannel& channel() { return channel_; }
  Message& message() { return message_; }

 private:
  bool send_tx_with(std::span<const cf32> tx, std::span<const std::uint8_t> extra);

  Settings settings_;
  MessageChannel channel_;
  Message message_;
  Welcome welcome_;
  Tick tick_;
  bool have_tick_ = false;
  std::uint64_t discontinuities_ = 0;
};

}  // namespace rfsitl::external
