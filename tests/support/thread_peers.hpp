#pragma once
/// A fake of cluster::Peers: K ranks in one process, one thread each, that
/// exchange through shared memory. Lets a test run a distributed engine
/// without MPI and compare it with one process.
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "rfsitl/cluster/peers.hpp"

namespace rfsitl::testing {

class ThreadPeerGroup {
 public:
  explicit ThreadPeerGroup(std::size_t ranks) : slots_(ranks) {
    for (std::size_t r = 0; r < ranks; ++r) members_.push_back(std::make_unique<Member>(*this, r));
  }
  cluster::Peers& peer(std::size_t rank) { return *members_[rank]; }
  /// Collective calls made by rank 0 so far (all ranks make as many).
  std::uint64_t exchanges() const {
    std::lock_guard lock(mutex_);
    return generation_;
  }

 private:
  class Member final : public cluster::Peers {
   public:
    Member(ThreadPeerGroup& group, std::size_t rank) : group_(group), rank_(rank) {}
    std::size_t rank() const override { return rank_; }
    std::size_t size() const override { return group_.slots_.size(); }
    void all_gather(std::span<const std::uint8_t> mine, cluster::Gathered& out) override {
      group_.all_gather(rank_, mine, out);
    }

   private:
    ThreadPeerGroup& group_;
    std::size_t rank_;
  };

  void all_gather(std::size_t rank, std::span<const std::uint8_t> mine, cluster::Gathered& out) {
    std::unique_lock lock(mutex_);
    slots_[rank].assign(mine.begin(), mine.end());
    const std::uint64_t generation = generation_;
    if (++arrived_ == slots_.size()) {
      // The last to arrive publishes; the others copy it before any of them
      // can complete the next exchange (which needs every rank again).
      published_.bytes.clear();
      published_.offsets.assign(1, 0);
      for (const auto& s : slots_) {
        published_.bytes.insert(published_.bytes.end(), s.begin(), s.end());
        published_.offsets.push_back(published_.bytes.size());
      }
      arrived_ = 0;
      ++generation_;
      changed_.notify_all();
    } else {
      changed_.wait(lock, [&] { return generation_ != generation; });
    }
    out = published_;
  }

  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<std::vector<std::uint8_t>> slots_;
  std::vector<std::unique_ptr<Member>> members_;
  cluster::Gathered published_;
  std::size_t arrived_ = 0;
  std::uint64_t generation_ = 0;
};

}  // namespace rfsitl::testing
