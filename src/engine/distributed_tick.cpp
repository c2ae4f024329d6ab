/// LockStepEngine in a distributed run: what its rank swaps with the others
/// every tick (transmissions) and every 0.1 s of virtual time (counters).
#include <stdexcept>
#include <string>
#include <utility>

#include "lock_step_engine.hpp"

namespace rfsitl::engine {

void LockStepEngine::exchange_transmissions() {
  TxMessage& mine = tx_out_;  // reused: its vectors keep their capacity
  mine.stop = local_stop_;
  mine.reports.clear();
  mine.samples.clear();
  mine.updates = inbox_.take();
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const Node& node = nodes_[i];
    if (!owned_[i] || !has_tx_report(node)) continue;
    mine.reports.push_back(tx_report_of(node));
    mine.samples.emplace_back(node.tx.data(), node.tx_samples);
  }
  const std::vector<TxMessageView>& all = link_->exchange_tx(mine);
  for (std::size_t r = 0; r < all.size(); ++r) {
    stop_agreed_ = stop_agreed_ || all[r].stop;
    peer_updates_.insert(peer_updates_.end(), all[r].updates.begin(), all[r].updates.end());
    if (r == link_->rank()) continue;
    for (std::size_t k = 0; k < all[r].reports.size(); ++k) take_report(r, k, all[r].reports[k]);
  }
}

void LockStepEngine::take_report(std::size_t rank, std::size_t k, const TxReport& t) {
  Node& node = nodes_[t.node];
  if (owned_[t.node]) {
    throw std::runtime_error("tick exchange: rank " + std::to_string(rank) +
                             " reports node index " + std::to_string(t.node) + ", owned here");
  }
  link_->copy_samples(rank, k, node.tx.data());
  take_tx_report(node, t);
}

void LockStepEngine::merge_counters() {
  ticks_since_merge_ = 0;
  std::vector<std::pair<std::uint32_t, NodeCountersSnapshot>> own;
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    if (owned_[i]) own.emplace_back(static_cast<std::uint32_t>(i), counters_[i].snapshot());
  }
  const RankFigures mine{clock_.max_lag_s(), clock_.late_ticks(), link_->bytes_sent(),
                         link_->wall_s(), clock_.elapsed_wall_s()};
  std::vector<RankFigures> figures;
  std::vector<std::pair<std::uint32_t, NodeCountersSnapshot>> all;
  std::vector<std::vector<ObserverShare>> shares;
  link_->exchange_counters(mine, own, reporter_.shares(), figures, all, shares);
  for (const auto& [node, snapshot] : all) {
    if (!owned_[node]) counters_[node].assign(snapshot);
  }
  for (std::size_t r = 0; r < shares.size(); ++r) {
    if (r != link_->rank()) reporter_.take_shares(r, shares[r]);
  }
  std::vector<RankStatus> ranks;
  for (const RankFigures& f : figures) {
    ranks.push_back({f.max_lag_s, f.late_ticks, f.exchanged_bytes, f.exchange_wall_s, f.wall_s});
  }
  std::lock_guard lock(snapshot_mutex_);
  ranks_snapshot_ = std::move(ranks);
}

}  // namespace rfsitl::engine
