#include "rfsitl/io/port_slot.hpp"

#include <algorithm>

#include <spdlog/spdlog.h>

namespace rfsitl::io {

void PortSlot::admit(std::shared_ptr<SlotMember> member) {
  if (!agent_ || !agent_->open()) {
    agent_ = std::move(member);
    spdlog::info("{}: agent connected", where_);
    return;
  }
  if (candidates_.size() >= kMaxCandidates) {
    candidates_.front()->close();
    candidates_.erase(candidates_.begin());
    // Logged the first few times, then one in a thousand: a connection flood
    // must not become a log flood.
    if (++overflow_closes_ <= 3 || overflow_closes_ % 1000 == 0) {
      spdlog::warn(
          "{}: more than {} connections waiting to take over; closed the oldest ({} so far)",
          where_, kMaxCandidates, overflow_closes_);
    }
  }
  candidates_.push_back(std::move(member));
}

void PortSlot::claim(const SlotMember* member, const char* why) {
  if (is_agent(member)) return;
  const auto it = std::find_if(candidates_.begin(), candidates_.end(),
                               [member](const auto& c) { return c.get() == member; });
  if (it == candidates_.end()) return;  // already closed
  std::shared_ptr<SlotMember> next = std::move(*it);
  candidates_.erase(it);
  if (agent_ && agent_->open()) {
    spdlog::warn("{}: a new connection {}: it replaces the agent connected before", where_, why);
    agent_->close();
  } else {
    spdlog::info("{}: agent connected", where_);
  }
  agent_ = std::move(next);
}

void PortSlot::closed(const SlotMember* member) {
  const auto it = std::find_if(candidates_.begin(), candidates_.end(),
                               [member](const auto& c) { return c.get() == member; });
  if (it != candidates_.end()) {
    candidates_.erase(it);
    return;
  }
  if (!is_agent(member)) return;
  agent_.reset();
  // The newest open candidate takes over; closed ones are dropped.
  while (!candidates_.empty()) {
    std::shared_ptr<SlotMember> next = std::move(candidates_.back());
    candidates_.pop_back();
    if (next->open()) {
      agent_ = std::move(next);
      spdlog::info("{}: agent disconnected; the connection waiting since then took over", where_);
      return;
    }
  }
  spdlog::info("{}: agent disconnected", where_);
}

void PortSlot::close_all() {
  if (agent_) agent_->close();
  for (const auto& c : candidates_) c->close();
}

}  // namespace rfsitl::io
