#pragma once
/// Bounded single-producer single-consumer queue without locks: the hand-off
/// between the I/O thread (producer) and the engine (consumer) of one node.
#include <atomic>
#include <cstddef>
#include <optional>
#include <vector>

namespace rfsitl {

template <typename T>
class SpscRing {
 public:
  /// Precondition: capacity >= 1.
  explicit SpscRing(std::size_t capacity) : slots_(capacity + 1) {}

  std::size_t capacity() const { return slots_.size() - 1; }

  /// Producer side. Returns false (and leaves `item` untouched) when full.
  bool try_push(T& item) {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    const std::size_t next = advance(head);
    if (next == tail_.load(std::memory_order_acquire)) return false;
    slots_[head] = std::move(item);
    head_.store(next, std::memory_order_release);
    return true;
  }

  /// Consumer side: the oldest item, or nullptr when empty. Valid until try_pop().
  T* peek() {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_.load(std::memory_order_acquire)) return nullptr;
    return &slots_[tail];
  }

  /// Consumer side.
  std::optional<T> try_pop() {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_.load(std::memory_order_acquire)) return std::nullopt;
    std::optional<T> item(std::move(slots_[tail]));
    slots_[tail] = T{};
    tail_.store(advance(tail), std::memory_order_release);
    return item;
  }

  /// Approximate when called concurrently with push/pop; exact otherwise.
  std::size_t size() const {
    const std::size_t head = head_.load(std::memory_order_acquire);
    const std::size_t tail = tail_.load(std::memory_order_acquire);
    return head >= tail ? head - tail : head + slots_.size() - tail;
  }

 private:
  std::size_t advance(std::size_t i) const { return i + 1 == slots_.size() ? 0 : i + 1; }

  std::vector<T> slots_;
  alignas(64) std::atomic<std::size_t> head_{0};  // next slot to write
  alignas(64) std::atomic<std::size_t> tail_{0};  // next slot to read
};

}  // namespace rfsitl
