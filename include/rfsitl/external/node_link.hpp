#pragma once
/// The emulator's connection to one external node. The hub's accept thread
/// offers admitted connections; the engine side adopts them at a tick boundary
/// and makes round trips with a timeout. A failed round trip (timeout, peer
/// gone, wrong reply) drops the connection, logs why and counts it; the node
/// is silent until its process connects again.
#include <atomic>
#include <cstdint>
#include <mutex>
#include <optional>
#include <span>
#include <string>

#include "rfsitl/external/message_channel.hpp"

namespace rfsitl::external {

class NodeLink {
 public:
  NodeLink(NodeId id, int reply_timeout_ms) : id_(id), reply_timeout_ms_(reply_timeout_ms) {}

  NodeId id() const { return id_; }

  /// Hub thread: hands over a connection that passed the handshake (replaces
  /// one that is still waiting to be adopted).
  void offer(MessageChannel&& channel, std::string program);

  /// Engine side, at a tick boundary: takes over an offered connection, closing
  /// the current one. Returns true when the node (re)joined just now.
  bool adopt();

  bool connected() const { return channel_.is_open(); }

  /// Engine side: sends one message and waits up to the reply timeout for a
  /// message of type `expect` with the same tick. Returns the reply (valid until
  /// the next call) or nullptr after dropping the connection.
  const Message* call(const MsgHeader& request, std::span<const cf32> samples,
                      std::span<const std::uint8_t> extra, MsgType expect);

  /// Drops the connection (logged with `why`); the node may join again.
  void drop(const std::string& why);

  // Any thread.
  std::uint64_t joins() const { return joins_.load(std::memory_order_relaxed); }
  std::uint64_t drops() const { return drops_.load(std::memory_order_relaxed); }
  std::uint64_t timeouts() const { return timeouts_.load(std::memory_order_relaxed); }
  bool ever_joined() const { return joins() > 0 || offered_.load(std::memory_order_acquire); }

 private:
  const NodeId id_;
  const int reply_timeout_ms_;
  MessageChannel channel_;  // engine side only
  Message reply_;
  std::string program_;

  std::mutex offer_mutex_;
  std::optional<MessageChannel> offered_channel_;
  std::string offered_program_;
  std::atomic<bool> offered_{false};

  std::atomic<std::uint64_t> joins_{0};
  std::atomic<std::uint64_t> drops_{0};
  std::atomic<std::uint64_t> timeouts_{0};
};

}  // namespace rfsitl::external
