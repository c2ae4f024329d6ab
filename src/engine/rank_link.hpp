#pragma once
// Internal to the engine: a rank's side of a distributed run's exchanges
// (cluster::Peers), with the message coding of tick_exchange.hpp and the
// figures of what it costs. Engine thread only.
#include <chrono>
#include <cstdint>
#include <vector>

#include "rfsitl/cluster/peers.hpp"
#include "tick_exchange.hpp"

namespace rfsitl::engine {

class RankLink {
 public:
  RankLink(cluster::Peers& peers, std::size_t nodes, std::size_t tick_samples)
      : peers_(peers), nodes_(nodes), tick_samples_(tick_samples) {}

  std::size_t rank() const { return peers_.rank(); }
  std::size_t ranks() const { return peers_.size(); }

  /// Collective: every rank's message A, by rank (valid until the next call).
  const std::vector<TxMessageView>& exchange_tx(const TxMessage& mine);
  /// Copies report `k` of rank `rank`'s last message A's samples into `out`.
  void copy_samples(std::size_t rank, std::size_t k, cf32* out) const;

  /// Collective: `ops` (this rank's, in node order) become every rank's, in
  /// node order (a node's ops in the order its owner made them).
  void exchange_ops(std::vector<LedgerOp>& ops);

  /// Collective: every rank's figures and observer shares (by rank) and its
  /// nodes' counters.
  void exchange_counters(const RankFigures& mine,
                         std::span<const std::pair<std::uint32_t, NodeCountersSnapshot>> own,
                         std::span<const ObserverShare> my_shares,
                         std::vector<RankFigures>& figures,
                         std::vector<std::pair<std::uint32_t, NodeCountersSnapshot>>& all,
                         std::vector<std::vector<ObserverShare>>& shares);

  /// Collective: returns when every rank has called it.
  void barrier();

  std::uint64_t bytes_sent() const { return bytes_sent_; }
  double wall_s() const { return wall_s_; }

 private:
  void gather(const std::vector<std::uint8_t>& mine);

  cluster::Peers& peers_;
  std::size_t nodes_;
  std::size_t tick_samples_;
  std::vector<std::uint8_t> out_;
  cluster::Gathered in_;
  std::vector<TxMessageView> views_;  // by rank, reused every tick
  std::vector<LedgerOp> merged_;      // exchange_ops' result, reused every tick
  std::uint64_t bytes_sent_ = 0;
  double wall_s_ = 0.0;
};

}  // namespace rfsitl::engine
