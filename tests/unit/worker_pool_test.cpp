#include "rfsitl/engine/worker_pool.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <thread>
#include <vector>

namespace rfsitl::engine {
namespace {

TEST(WorkerPool, SizeIsTheRequestedWorkerCount) {
  for (std::size_t n : {1U, 2U, 4U}) {
    WorkerPool pool(n);
    EXPECT_EQ(pool.size(), n);
  }
}

TEST(WorkerPool, EveryWorkerIndexRunsExactlyOncePerRun) {
  for (std::size_t n : {1U, 2U, 4U}) {
    WorkerPool pool(n);
    std::vector<std::atomic<int>> calls(n + 1);  // one extra: an out-of-range index lands here
    for (int r = 0; r < 3; ++r) {
      pool.run([&](std::size_t w) { calls[std::min(w, n)].fetch_add(1); });
      for (std::size_t w = 0; w < n; ++w) EXPECT_EQ(calls[w].load(), r + 1) << "pool " << n;
      EXPECT_EQ(calls[n].load(), 0) << "pool " << n;
    }
  }
}

TEST(WorkerPool, RunReturnsOnlyAfterEveryTaskFinished) {
  WorkerPool pool(4);
  std::vector<int> slots(4, 0);  // plain ints: run()'s return must publish the writes
  pool.run([&](std::size_t w) {
    // Later workers finish later; worker 0 (the caller) returns first.
    std::this_thread::sleep_for(std::chrono::milliseconds(20 * w));
    slots[w] = static_cast<int>(w) + 100;
  });
  for (std::size_t w = 0; w < 4; ++w) EXPECT_EQ(slots[w], static_cast<int>(w) + 100);
}

TEST(WorkerPool, TenThousandConsecutiveRunsEachCompleteFully) {
  constexpr std::uint64_t kRuns = 10'000;
  for (std::size_t n : {1U, 2U, 4U}) {
    WorkerPool pool(n);
    std::vector<std::uint64_t> per_worker(n, 0);  // each slot written by one worker only
    std::atomic<std::uint64_t> total{0};
    std::uint64_t incomplete_runs = 0;
    for (std::uint64_t r = 0; r < kRuns; ++r) {
      pool.run([&](std::size_t w) {
        ++per_worker[w];
        total.fetch_add(1, std::memory_order_relaxed);
      });
      if (total.load(std::memory_order_relaxed) != (r + 1) * n) ++incomplete_runs;
    }
    EXPECT_EQ(incomplete_runs, 0U) << "pool " << n;
    for (std::size_t w = 0; w < n; ++w) EXPECT_EQ(per_worker[w], kRuns) << "pool " << n;
  }
}

TEST(WorkerPool, ConsecutiveRunsSeeEachOthersResults) {
  // Phase k reads what every worker wrote in phase k - 1, as the engine's TX and
  // RX phases do: the barrier must order them.
  WorkerPool pool(4);
  std::vector<std::uint64_t> value(4, 0);
  std::atomic<std::uint64_t> mismatches{0};
  for (std::uint64_t k = 1; k <= 2000; ++k) {
    pool.run([&](std::size_t w) {
      const std::uint64_t neighbour = value[(w + 1) % 4];
      if (neighbour != k - 1) mismatches.fetch_add(1);
    });
    pool.run([&](std::size_t w) { value[w] = k; });
  }
  EXPECT_EQ(mismatches.load(), 0U);
}

TEST(WorkerPool, ForEachRunsEveryItemExactlyOnceOnAnyNumberOfWorkers) {
  WorkerPool pool(4);
  for (const std::size_t workers : {1U, 2U, 4U, 9U}) {
    for (const std::size_t count : {0U, 1U, 5U, 1000U}) {
      std::vector<std::atomic<int>> runs(count);
      pool.for_each(count, workers, [&](std::size_t j) { runs[j].fetch_add(1); });
      for (std::size_t j = 0; j < count; ++j) {
        ASSERT_EQ(runs[j].load(), 1) << workers << " workers, item " << j << " of " << count;
      }
    }
  }
}

TEST(WorkerPool, ForEachLetsTheOtherWorkersTakeTheItemsOfOneThatIsHeldUp) {
  // Item 0 holds its worker until every other item has run: with shares
  // fixed in advance (item j on worker j % 2) this would never finish; with
  // each worker taking the next free item, the other worker runs them all.
  WorkerPool pool(2);
  constexpr std::size_t kItems = 64;
  std::atomic<std::size_t> done{0};
  std::atomic<bool> gave_up{false};
  pool.for_each(kItems, 2, [&](std::size_t j) {
    if (j == 0) {
      const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
      while (done.load() < kItems - 1) {
        if (std::chrono::steady_clock::now() > deadline) {
          gave_up = true;
          break;
        }
        std::this_thread::yield();
      }
    }
    done.fetch_add(1);
  });
  EXPECT_FALSE(gave_up.load());
  EXPECT_EQ(done.load(), kItems);
}

}  // namespace
}  // namespace rfsitl::engine
