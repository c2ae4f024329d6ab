#pragma once
/// One end of an external-transceiver connection: sends and receives whole
/// protocol messages (see wire_protocol.hpp) on a Unix SOCK_SEQPACKET socket,
/// with explicit timeouts. Not thread-safe: one user at a time.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "rfsitl/common/types.hpp"
#include "rfsitl/external/client/wire_protocol.hpp"

namespace rfsitl::external {

/// A received message; `samples` and `extra` are reused between receives.
struct Message {
  MsgHeader header;
  std::vector<cf32> samples;
  std::vector<std::uint8_t> extra;

  MsgType type() const { return static_cast<MsgType>(header.type); }
  std::string extra_text() const { return {extra.begin(), extra.end()}; }
};

enum class RecvStatus {
  kOk,
  kTimeout,    ///< nothing arrived in time; the connection is still usable
  kClosed,     ///< the peer closed the connection
  kMalformed,  ///< bad magic or sizes that do not add up; the connection should be dropped
};

class MessageChannel {
 public:
  MessageChannel() = default;
  /// Takes ownership of a connected SOCK_SEQPACKET descriptor.
  explicit MessageChannel(int fd);
  ~MessageChannel();
  MessageChannel(MessageChannel&& other) noexcept;
  MessageChannel& operator=(MessageChannel&& other) noexcept;
  MessageChannel(const MessageChannel&) = delete;
  MessageChannel& operator=(const MessageChannel&) = delete;

  /// Connects to the emulator's socket at `path`. Throws std::runtime_error
  /// naming the path and the system's reason.
  static MessageChannel connect_to(const std::string& path);

  bool is_open() const { return fd_ >= 0; }
  int fd() const { return fd_; }
  void close();

  /// Sends one message (header.count and header.extra_bytes are set from the
  /// spans). Returns false if the peer is gone (the channel is then closed).
  /// Never blocks for long: the socket buffer holds several messages.
  bool send(MsgHeader header, std::span<const cf32> samples = {},
            std::span<const std::uint8_t> extra = {});

  /// Waits up to `timeout_ms` (negative: forever) for one message.
  RecvStatus receive(Message& out, int timeout_ms);

 private:
  int fd_ = -1;
  std::vector<std::uint8_t> buffer_;
};

/// Human-readable name of a message type, for logs ("tick", "tx", ...).
const char* message_type_name(std::uint16_t type);

}  // namespace rfsitl::external
