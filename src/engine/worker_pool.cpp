#include "rfsitl/engine/worker_pool.hpp"

#include <algorithm>

namespace rfsitl::engine {
namespace {

constexpr int kSpinIterations = 4000;

// Waits until `value` differs from `old`: spin first, then block.
template <typename T>
T wait_change(const std::atomic<T>& value, T old) {
  for (int i = 0; i < kSpinIterations; ++i) {
    const T v = value.load(std::memory_order_acquire);
    if (v != old) return v;
  }
  value.wait(old, std::memory_order_acquire);
  return value.load(std::memory_order_acquire);
}

}  // namespace

WorkerPool::WorkerPool(std::size_t workers) {
  for (std::size_t i = 1; i < workers; ++i) threads_.emplace_back([this, i] { worker_loop(i); });
}

WorkerPool::~WorkerPool() {
  stop_.store(true, std::memory_order_release);
  generation_.fetch_add(1, std::memory_order_acq_rel);
  generation_.notify_all();
  for (auto& t : threads_) t.join();
}

void WorkerPool::run(const std::function<void(std::size_t)>& task) {
  if (threads_.empty()) {
    task(0);
    return;
  }
  task_ = &task;
  remaining_.store(threads_.size(), std::memory_order_release);
  generation_.fetch_add(1, std::memory_order_acq_rel);
  generation_.notify_all();
  task(0);
  for (std::size_t left = remaining_.load(std::memory_order_acquire); left != 0;
       left = remaining_.load(std::memory_order_acquire)) {
    wait_change(remaining_, left);
  }
}

void WorkerPool::for_each(std::size_t count, std::size_t workers,
                          const std::function<void(std::size_t)>& item) {
  if (workers <= 1 || threads_.empty() || count <= 1) {
    for (std::size_t j = 0; j < count; ++j) item(j);
    return;
  }
  // The phase's shape in members, so that the task run() gets captures only
  // `this` and fits std::function's inline storage: no allocation per tick.
  next_item_.store(0, std::memory_order_relaxed);
  for_count_ = count;
  for_workers_ = std::min(workers, size());
  for_item_ = &item;
  run(for_each_task_);
}

void WorkerPool::worker_loop(std::size_t index) {
  std::uint64_t seen = 0;
  for (;;) {
    seen = wait_change(generation_, seen);
    if (stop_.load(std::memory_order_acquire)) return;
    (*task_)(index);
    if (remaining_.fetch_sub(1, std::memory_order_acq_rel) == 1) remaining_.notify_one();
  }
}

}  // namespace rfsitl::engine
