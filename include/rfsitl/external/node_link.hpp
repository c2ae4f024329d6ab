#pragma once
/// The emulator's connection to one external node. The hub's accept thread
/// offers admitted connections; the engine side adopts them at a tick boundary
/// and makes round trips with a timeout. A failed round trip (timeout, peer
/// gone, wrong reply), a peer that closes an idle connection, or a new
/// connection of the same node while the old one is still up drops the old
/// connection, logs why and counts it (so joins() - drops() is 1 while a
/// process is connected, else 0); the node is silent until its process
/// connects again. A timeout is also a stall: the engine waits for the reply,
/// so the whole emulation stands still for the reply timeout each time.
#include <atomic>
#include <cstdint>
#include <mutex>
#include <optional>
#include <span>
#include <string>

#include "rfsitl/external/client/message_channel.hpp"

namespace rfsitl::external {

class NodeLink {
 public:
  NodeLink(NodeId id, int reply_timeout_ms) : id_(id), reply_timeout_ms_(reply_timeout_ms) {}

  NodeId id() const { return id_; }

  /// Hub thread: hands over a connection that passed the handshake (replaces
  /// one that is still waiting to be adopted).
  void offer(MessageChannel&& channel, std::string program);

  /// Engine side, at a tick boundary: takes over an offered connection. A
  /// current connection is dropped first (its process restarted or another
  /// one took the node over) and counted as a drop. Returns true when the node
  /// (re)joined just now.
  bool adopt();

  bool connected() const { return channel_.is_open(); }

  /// Calls of watch_peer() per actual check (a poll() system call).
  static constexpr std::uint32_t kPeerCheckEvery = 16;

  /// Engine side, at a tick boundary with no round trip in flight: drops the
  /// connection if its process has closed it (died, exited), which an idle
  /// link would otherwise notice only at its next round trip. Checks on every
  /// kPeerCheckEvery-th call, so that it costs little when called every tick.
  /// Returns false if the link is (now) not connected.
  bool watch_peer();

  /// Engine side: sends one message and waits up to the reply timeout for a
  /// message of type `expect` with the same tick. Returns the reply (valid until
  /// the next call) or nullptr after dropping the connection.
  const Message* call(const MsgHeader& request, std::span<const cf32> samples,
                      std::span<const std::uint8_t> extra, MsgType expect);

  /// Drops the connection (logged with `why`); the node may join again.
  void drop(const std::string& why);

  /// Engine side, before the first round trip: also counts every timeout
  /// (stall) in `counter` (the node's NodeCounters::external_stalls, so that
  /// the summary, /api/stats, /metrics and the dashboard show it). `counter`
  /// must outlive the engine's use of this link.
  void count_stalls_in(std::atomic<std::uint64_t>& counter) { stall_counter_ = &counter; }

  // Any thread.
  std::uint64_t joins() const { return joins_.load(std::memory_order_relaxed); }
  std::uint64_t drops() const { return drops_.load(std::memory_order_relaxed); }
  std::uint64_t timeouts() const { return timeouts_.load(std::memory_order_relaxed); }
  bool ever_joined() const { return joins() > 0 || offered_.load(std::memory_order_acquire); }
  /// A process holds the node (joins() > drops()) or has been admitted and
  /// waits to be adopted at the next tick boundary. For discovery: a snapshot
  /// that may be stale by the time anyone reads it.
  bool claimed() const;

 private:
  // Closes the connection, counts the drop and logs it; `replaced`: a new
  // connection of the node takes over at once.
  void count_drop(const std::string& why, bool replaced);

  const NodeId id_;
  const int reply_timeout_ms_;
  MessageChannel channel_;  // engine side only
  Message reply_;
  std::string program_;
  std::uint32_t watch_calls_ = 0;                        // engine side only
  std::atomic<std::uint64_t>* stall_counter_ = nullptr;  // engine side only

  mutable std::mutex offer_mutex_;
  std::optional<MessageChannel> offered_channel_;
  std::string offered_program_;
  std::atomic<bool> offered_{false};

  std::atomic<std::uint64_t> joins_{0};
  std::atomic<std::uint64_t> drops_{0};
  std::atomic<std::uint64_t> timeouts_{0};
};

}  // namespace rfsitl::external
