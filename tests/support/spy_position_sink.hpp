#pragma once
// A PositionSink that records every report, for testing position sources
// without an engine. Thread-safe: sources report from their own threads.
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <utility>
#include <vector>

#include "rfsitl/position/source/position_source.hpp"

namespace rfsitl::test {

class SpyPositionSink final : public position::PositionSink {
 public:
  void report(std::size_t index, const position::StateReport& report) override {
    std::lock_guard lock(mutex_);
    reports_.emplace_back(index, report);
    changed_.notify_all();
  }

  /// Waits (up to `timeout`) until at least `n` reports have come; returns them
  /// all, however many that is.
  std::vector<std::pair<std::size_t, position::StateReport>> wait_for(
      std::size_t n, std::chrono::milliseconds timeout = std::chrono::seconds(20)) {
    std::unique_lock lock(mutex_);
    changed_.wait_for(lock, timeout, [&] { return reports_.size() >= n; });
    return reports_;
  }

  std::size_t count() const {
    std::lock_guard lock(mutex_);
    return reports_.size();
  }

 private:
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<std::pair<std::size_t, position::StateReport>> reports_;
};

}  // namespace rfsitl::test
