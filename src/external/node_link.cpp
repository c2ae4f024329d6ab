#include "rfsitl/external/node_link.hpp"

#include <poll.h>

#include <cerrno>

#include <spdlog/spdlog.h>

#include "rfsitl/common/log_text.hpp"

namespace rfsitl::external {

void NodeLink::offer(MessageChannel&& channel, std::string program) {
  std::lock_guard lock(offer_mutex_);
  offered_channel_.emplace(std::move(channel));
  offered_program_ = std::move(program);
  offered_.store(true, std::memory_order_release);
}

bool NodeLink::adopt() {
  if (!offered_.load(std::memory_order_acquire)) return false;
  std::lock_guard lock(offer_mutex_);
  if (!offered_channel_) return false;
  // The new connection is counted before the old one is closed: the old
  // peer may try to claim the node again the moment it sees its socket
  // close, and claimed() must not find joins == drops in between.
  joins_.fetch_add(1, std::memory_order_relaxed);
  // The old connection ends here whether or not its process is still alive
  // (a restarted child's old socket may not have been noticed closed yet):
  // count it, so that joins - drops stays the number of live connections.
  if (channel_.is_open()) count_drop("a new connection of the node replaces it", true);
  channel_ = std::move(*offered_channel_);
  offered_channel_.reset();
  program_ = std::move(offered_program_);
  spdlog::info("node {}: external transceiver '{}' joined", id_, log_text(program_));
  return true;
}

bool NodeLink::claimed() const {
  // offered_ stays true after the first adoption (ever_joined() reads it), so
  // a pending offer is the channel itself, under the mutex.
  // Under the offer's mutex, so that an adoption (which moves the offer into
  // a join) is seen whole.
  std::lock_guard lock(offer_mutex_);
  if (joins() > drops()) return true;
  if (!offered_channel_) return false;
  // An offer whose process has gone again (a probe that opened the device and
  // exited before the engine ran) claims nothing.
  pollfd p{offered_channel_->fd(), POLLRDHUP, 0};
  return ::poll(&p, 1, 0) == 0;
}

void NodeLink::drop(const std::string& why) {
  // A channel that send() or receive() already closed still counts as a drop.
  count_drop(why, false);
}

void NodeLink::count_drop(const std::string& why, bool replaced) {
  // Counted and logged before the peer can see the socket close, so that what
  // it observes is already in the books.
  drops_.fetch_add(1, std::memory_order_relaxed);
  spdlog::warn("node {}: external transceiver '{}' dropped: {}{}", id_, log_text(program_), why,
               replaced ? "" : "; the node is silent until it connects again");
  channel_.close();
}

bool NodeLink::watch_peer() {
  if (!channel_.is_open()) return false;
  if (++watch_calls_ % kPeerCheckEvery != 0) return true;
  // Between round trips nothing is due from the peer, so readable data is
  // left for the next call() to judge; only a hang-up or error means the
  // process is gone (a dead process's end of the socket pair is closed by the
  // kernel, which shows as POLLHUP here).
  pollfd p{channel_.fd(), POLLIN | POLLRDHUP, 0};
  int r;
  do {
    r = ::poll(&p, 1, 0);
  } while (r < 0 && errno == EINTR);
  if (r <= 0) return true;
  if ((p.revents & (POLLHUP | POLLRDHUP | POLLERR | POLLNVAL)) == 0) return true;
  drop("the process closed the connection while idle");
  return false;
}

const Message* NodeLink::call(const MsgHeader& request, std::span<const cf32> samples,
                              std::span<const std::uint8_t> extra, MsgType expect) {
  if (!channel_.send(request, samples, extra)) {
    drop("the process is gone (send failed)");
    return nullptr;
  }
  switch (channel_.receive(reply_, reply_timeout_ms_)) {
    case RecvStatus::kOk:
      break;
    case RecvStatus::kTimeout: {
      const std::uint64_t stalls = timeouts_.fetch_add(1, std::memory_order_relaxed) + 1;
      if (stall_counter_ != nullptr) stall_counter_->fetch_add(1, std::memory_order_relaxed);
      drop("no reply within " + std::to_string(reply_timeout_ms_) + " ms (tick " +
           std::to_string(request.tick) + "): the engine stalled that long waiting for it (stall " +
           std::to_string(stalls) + " of this node)");
      return nullptr;
    }
    case RecvStatus::kClosed:
      drop("the process closed the connection");
      return nullptr;
    case RecvStatus::kMalformed:
      drop("malformed message");
      return nullptr;
  }
  if (reply_.type() != expect || reply_.header.tick != request.tick) {
    drop(std::string("expected ") + message_type_name(static_cast<std::uint16_t>(expect)) +
         " for tick " + std::to_string(request.tick) + ", got " +
         message_type_name(reply_.header.type) + " for tick " + std::to_string(reply_.header.tick));
    return nullptr;
  }
  return &reply_;
}

}  // namespace rfsitl::external
