#include "rfsitl/external/node_link.hpp"

#include <spdlog/spdlog.h>

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
  if (channel_.is_open())
    spdlog::warn("node {}: a new external connection replaces the old one", id_);
  channel_ = std::move(*offered_channel_);
  offered_channel_.reset();
  program_ = std::move(offered_program_);
  joins_.fetch_add(1, std::memory_order_relaxed);
  spdlog::info("node {}: external transceiver '{}' joined", id_, program_);
  return true;
}

void NodeLink::drop(const std::string& why) {
  // A channel that send() or receive() already closed still counts as a drop.
  channel_.close();
  drops_.fetch_add(1, std::memory_order_relaxed);
  spdlog::warn(
      "node {}: external transceiver '{}' dropped: {}; the node is silent until it "
      "connects again",
      id_, program_, why);
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
    case RecvStatus::kTimeout:
      timeouts_.fetch_add(1, std::memory_order_relaxed);
      drop("no reply within " + std::to_string(reply_timeout_ms_) + " ms (tick " +
           std::to_string(request.tick) + ")");
      return nullptr;
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
