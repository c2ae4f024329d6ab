#pragma once
/// Fixed threads that run one phase of a tick in parallel and meet at a
/// barrier. The calling thread takes part as worker 0, so a pool of one has no
/// extra thread. Waiting spins briefly, then sleeps on an atomic (ticks are
/// ~1 ms apart: a futex wake costs far less than a missed tick).
#include <atomic>
#include <cstddef>
#include <functional>
#include <thread>
#include <vector>

namespace rfsitl::engine {

class WorkerPool {
 public:
  /// Precondition: workers >= 1.
  explicit WorkerPool(std::size_t workers);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  std::size_t size() const { return threads_.size() + 1; }

  /// Runs task(worker) for worker = 0..size()-1 concurrently; returns when all
  /// have finished. Not reentrant. The task must not throw.
  void run(const std::function<void(std::size_t)>& task);

  /// Runs item(j) for j = 0..count-1 on `workers` of the pool's threads (the
  /// caller's among them; 1: the caller alone, no thread woken; clamped to
  /// size()). Each takes the next index when it is done with its last, so a
  /// worker the OS holds up (another process, a hypervisor's steal) delays
  /// only the item it holds, not a share fixed in advance. Returns when all
  /// have run. Not reentrant; item must not throw.
  void for_each(std::size_t count, std::size_t workers,
                const std::function<void(std::size_t)>& item);

 private:
  void worker_loop(std::size_t index);

  std::vector<std::thread> threads_;
  const std::function<void(std::size_t)>* task_ = nullptr;
  std::atomic<std::uint64_t> generation_{0};
  std::atomic<std::size_t> remaining_{0};
  std::atomic<bool> stop_{false};
  std::atomic<std::size_t> next_item_{0};  // for_each's next index
  // The for_each under way (set before run(), read by its workers after the
  // generation's release): its size, workers and item.
  std::size_t for_count_ = 0;
  std::size_t for_workers_ = 0;
  const std::function<void(std::size_t)>* for_item_ = nullptr;
  const std::function<void(std::size_t)> for_each_task_ = [this](std::size_t w) {
    if (w >= for_workers_) return;
    for (std::size_t j = next_item_.fetch_add(1, std::memory_order_relaxed); j < for_count_;
         j = next_item_.fetch_add(1, std::memory_order_relaxed)) {
      (*for_item_)(j);
    }
  };
};

}  // namespace rfsitl::engine
