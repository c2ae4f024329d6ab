#pragma once
/// The messages waiting to be written to one dashboard viewer. A viewer that
/// reads slowly, or never, must not grow the server's memory: the queue holds
/// at most kCapacity messages (plus the two a viewer gets first), whatever the
/// kind. Single-threaded (the dashboard's I/O thread).
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <utility>

namespace rfsitl::monitor {

enum class MessageKind : std::uint8_t {
  kEssential,  ///< hello: never dropped (sent once, first)
  kSnapshot,   ///< periodic; a newer one replaces a queued one
  kSpectrum,   ///< periodic; a newer one replaces a queued one
  kEvent,      ///< constellation, error reply: dropped oldest first when full
};

struct OutgoingMessage {
  std::shared_ptr<const std::string> text;
  MessageKind kind = MessageKind::kEvent;
  bool carries_snr = false;  ///< a snapshot with the link matrix (later ones may omit it)
};

class ViewerQueue {
 public:
  static constexpr std::size_t kCapacity = 16;

  /// Queues `m`. A periodic message replaces the queued (not yet writing)
  /// message of its kind; when the queue is full, the oldest message that is
  /// neither essential nor being written is dropped to make room (or `m`
  /// itself, if nothing else can go). Returns how many messages were dropped.
  std::size_t push(OutgoingMessage m);

  bool empty() const { return queue_.empty(); }
  bool writing() const { return writing_; }
  std::size_t size() const { return queue_.size(); }
  /// The oldest message (precondition: !empty()).
  const OutgoingMessage& front() const { return queue_.front(); }
  /// The message to write next; marks it as being written (never dropped).
  const OutgoingMessage& start_front();
  /// The front was written.
  void pop_front();
  void clear() { queue_.clear(), writing_ = false; }

  /// True once a dropped snapshot carried the link matrix the viewer has not
  /// had since: the next snapshot must carry it. Reading clears it.
  bool take_lost_snr() { return std::exchange(lost_snr_, false); }
  std::uint64_t dropped() const { return dropped_; }
  std::size_t peak() const { return peak_; }

 private:
  void drop(std::deque<OutgoingMessage>::iterator it);

  std::deque<OutgoingMessage> queue_;
  bool writing_ = false;  // queue_.front() is being written
  bool lost_snr_ = false;
  std::uint64_t dropped_ = 0;
  std::size_t peak_ = 0;
};

}  // namespace rfsitl::monitor
