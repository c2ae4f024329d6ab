#pragma once
/// Exponential backoff for reconnection attempts: a process that cannot join
/// (the emulator refuses it, or is not there yet) retries quickly at first and
/// then ever more slowly, so that it neither floods the emulator nor waits
/// long once the emulator is ready.
#include <algorithm>
#include <chrono>

namespace rfsitl {

class RetryBackoff {
 public:
  using Duration = std::chrono::milliseconds;

  /// Delays `first`, 2 first, 4 first, ... up to `cap`, then `cap` forever.
  /// A `first` below 1 ms counts as 1 ms; a `cap` below `first` as `first`.
  RetryBackoff(Duration first, Duration cap)
      : first_(std::max(first, Duration(1))), cap_(std::max(cap, first_)), next_(first_) {}

  /// The pause before the next attempt; doubles the one after.
  Duration next() {
    const Duration d = next_;
    next_ = next_ >= cap_ / 2 ? cap_ : next_ * 2;
    return d;
  }

  /// Starts over at `first` (after a success).
  void reset() { next_ = first_; }

 private:
  Duration first_;
  Duration cap_;
  Duration next_;
};

}  // namespace rfsitl
