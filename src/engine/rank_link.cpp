#include "rank_link.hpp"

#include <algorithm>
#include <cstring>

namespace rfsitl::engine {

void RankLink::gather(const std::vector<std::uint8_t>& mine) {
  const auto t0 = std::chrono::steady_clock::now();
  peers_.all_gather(mine, in_);
  wall_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // What the others receive from this rank (an all-gather sends it to each).
  bytes_sent_ += mine.size() * (peers_.size() - 1);
}

const std::vector<TxMessageView>& RankLink::exchange_tx(const TxMessage& mine) {
  write_tx_message(mine, out_);
  gather(out_);
  views_.resize(in_.ranks());
  for (std::size_t r = 0; r < in_.ranks(); ++r) {
    read_tx_message(in_.of(r), r, nodes_, tick_samples_, views_[r]);
  }
  return views_;
}

void RankLink::copy_samples(std::size_t rank, std::size_t k, cf32* out) const {
  const TxMessageView& v = views_[rank];
  std::memcpy(out, in_.of(rank).data() + v.sample_offsets[k],
              v.reports[k].tx_samples * sizeof(cf32));
}

void RankLink::exchange_ops(std::vector<LedgerOp>& ops) {
  write_ledger_ops(ops, out_);
  gather(out_);
  // This rank's own ops keep their deliveries; the others' are read back.
  merged_.clear();
  for (std::size_t r = 0; r < in_.ranks(); ++r) {
    if (r == rank()) {
      merged_.insert(merged_.end(), ops.begin(), ops.end());
    } else {
      read_ledger_ops(in_.of(r), r, nodes_, merged_);
    }
  }
  // Every node belongs to one rank, so sorting by node keeps each node's ops in order.
  std::stable_sort(merged_.begin(), merged_.end(),
                   [](const LedgerOp& a, const LedgerOp& b) { return a.node < b.node; });
  ops.swap(merged_);  // both keep their capacity for the next tick
}

void RankLink::exchange_counters(
    const RankFigures& mine, std::span<const std::pair<std::uint32_t, NodeCountersSnapshot>> own,
    std::span<const ObserverShare> my_shares, std::vector<RankFigures>& figures,
    std::vector<std::pair<std::uint32_t, NodeCountersSnapshot>>& all,
    std::vector<std::vector<ObserverShare>>& shares) {
  write_counters(mine, own, my_shares, out_);
  gather(out_);
  figures.assign(in_.ranks(), RankFigures{});
  shares.assign(in_.ranks(), {});
  all.clear();
  for (std::size_t r = 0; r < in_.ranks(); ++r)
    read_counters(in_.of(r), r, nodes_, figures[r], all, shares[r]);
}

void RankLink::barrier() {
  out_.clear();
  peers_.all_gather(out_, in_);
}

}  // namespace rfsitl::engine
