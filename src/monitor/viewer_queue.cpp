#include "rfsitl/monitor/viewer_queue.hpp"

#include <algorithm>
#include <utility>

namespace rfsitl::monitor {

void ViewerQueue::drop(std::deque<OutgoingMessage>::iterator it) {
  queue_.erase(it);
  ++dropped_;
}

std::size_t ViewerQueue::push(OutgoingMessage m) {
  const std::uint64_t before = dropped_;
  // The message being written stays: Beast is still reading its buffer.
  const auto first_free = queue_.begin() + (writing_ ? 1 : 0);
  const bool periodic = m.kind == MessageKind::kSnapshot || m.kind == MessageKind::kSpectrum;
  if (periodic) {
    const auto same = std::find_if(first_free, queue_.end(),
                                   [&](const OutgoingMessage& q) { return q.kind == m.kind; });
    if (same != queue_.end()) {
      const bool snr_lost = same->carries_snr && !m.carries_snr;
      drop(same);
      lost_snr_ = lost_snr_ || snr_lost;
    }
  }
  if (queue_.size() >= kCapacity && m.kind != MessageKind::kEssential) {
    const auto victim =
        std::find_if(queue_.begin() + (writing_ ? 1 : 0), queue_.end(),
                     [](const OutgoingMessage& q) { return q.kind != MessageKind::kEssential; });
    if (victim == queue_.end()) {
      if (m.carries_snr) lost_snr_ = true;
      ++dropped_;
      return static_cast<std::size_t>(dropped_ - before);
    }
    lost_snr_ = lost_snr_ || victim->carries_snr;
    drop(victim);
  }
  queue_.push_back(std::move(m));
  peak_ = std::max(peak_, queue_.size());
  return static_cast<std::size_t>(dropped_ - before);
}

const OutgoingMessage& ViewerQueue::start_front() {
  writing_ = true;
  return queue_.front();
}

void ViewerQueue::pop_front() {
  queue_.pop_front();
  writing_ = false;
}

}  // namespace rfsitl::monitor
