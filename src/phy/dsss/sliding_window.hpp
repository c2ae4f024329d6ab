#pragma once
// Internal to the DSSS receiver: a stream of values indexed by absolute sample
// number, of which the newest `history` before the current block stay readable.
#include <algorithm>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rfsitl::phy::dsss::detail {

template <typename T>
class SlidingWindow {
 public:
  /// Keeps `history` values before each block of at most `max_block` values.
  /// The stream starts at absolute index 0 with `history` zeros before it, so
  /// that every filter can read its full span from the first sample on.
  void configure(std::size_t history, std::size_t max_block, std::int64_t start = 0) {
    history_ = history;
    // Compacting copies `history` values; a capacity of several histories
    // plus blocks makes that cost a fraction of a copy per sample.
    buffer_.assign(3 * history + 4 * max_block, T{});
    reset(start);
  }

  /// Restarts the stream at absolute index `start` with a zero history.
  void reset(std::int64_t start = 0) {
    std::fill(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(history_), T{});
    base_ = start - static_cast<std::int64_t>(history_);
    size_ = history_;
  }

  /// Appends `count` values (uninitialized: the caller writes them) and returns
  /// a pointer to the first. Precondition: count <= max_block.
  T* append(std::size_t count) {
    if (size_ + count > buffer_.size()) {
      const std::size_t drop = size_ - history_;
      std::copy(buffer_.begin() + static_cast<std::ptrdiff_t>(drop),
                buffer_.begin() + static_cast<std::ptrdiff_t>(size_), buffer_.begin());
      base_ += static_cast<std::int64_t>(drop);
      size_ = history_;
    }
    assert(size_ + count <= buffer_.size());
    T* p = buffer_.data() + size_;
    size_ += count;
    return p;
  }

  /// One past the newest absolute index.
  std::int64_t end() const { return base_ + static_cast<std::int64_t>(size_); }

  /// The value at absolute index n. Precondition: end() - size() <= n < end().
  T* at(std::int64_t n) {
    assert(n >= base_ && n < end());
    return buffer_.data() + (n - base_);
  }
  const T* at(std::int64_t n) const {
    assert(n >= base_ && n < end());
    return buffer_.data() + (n - base_);
  }

  /// Oldest readable absolute index.
  std::int64_t begin() const { return base_; }

 private:
  std::vector<T> buffer_;
  std::size_t history_ = 0;
  std::int64_t base_ = 0;
  std::size_t size_ = 0;
};

}  // namespace rfsitl::phy::dsss::detail
