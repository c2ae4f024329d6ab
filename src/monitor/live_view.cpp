#include "rfsitl/monitor/live_view.hpp"

#include <algorithm>
#include <stdexcept>

#include "rfsitl/monitor/live_view_share.hpp"

namespace rfsitl::monitor {

LiveView::LiveView(std::vector<NodeId> ids)
    : ids_(std::move(ids)),
      n_(ids_.size()),
      watchers_(new std::atomic<int>[n_]),
      averagers_(n_),
      published_(n_),
      next_time_(n_, -1),
      constellations_(n_),
      shared_until_(n_, -1),
      remote_watchers_(new std::atomic<int>[n_]) {
  links_.received.assign(n_ * n_, 0);
  links_.lost.assign(n_ * n_, 0);
  shared_links_ = links_;
  for (std::size_t i = 0; i < n_; ++i) {
    watchers_[i].store(0);
    remote_watchers_[i].store(0);
  }
}

std::optional<std::size_t> LiveView::index_of(NodeId id) const {
  const auto it = std::find(ids_.begin(), ids_.end(), id);
  if (it == ids_.end()) return std::nullopt;
  return static_cast<std::size_t>(it - ids_.begin());
}

void LiveView::on_frame_event(const engine::FrameEvent& e) {
  using K = engine::FrameEventKind;
  if (e.kind != K::kReceived && e.kind != K::kLost) return;
  // The sender is the serial's top byte (the engine's numbering); the receiver
  // is the event's node (received) or the destination (lost unicast).
  const std::size_t tx = e.serial >> 24;
  const auto rx = e.kind == K::kReceived ? index_of(e.node) : index_of(e.dst);
  if (tx >= n_ || !rx) return;
  std::lock_guard lock(links_mutex_);
  auto& v = e.kind == K::kReceived ? links_.received : links_.lost;
  ++v[tx * n_ + *rx];
}

LiveView::LinkOutcomes LiveView::link_outcomes() const {
  std::lock_guard lock(links_mutex_);
  LinkOutcomes sum = links_;
  for (const LinkOutcomes& r : remote_links_) {
    for (std::size_t k = 0; k < r.received.size(); ++k) {
      sum.received[k] += r.received[k];
      sum.lost[k] += r.lost[k];
    }
  }
  return sum;
}

bool LiveView::wants_samples(std::size_t node, SampleTime tick_start,
                             std::size_t tick_samples) const {
  if (node >= n_ || (watchers_[node].load(std::memory_order_relaxed) <= 0 &&
                     remote_watchers_[node].load(std::memory_order_relaxed) <= 0)) {
    return false;
  }
  const auto tick = static_cast<std::size_t>(tick_start) / std::max<std::size_t>(tick_samples, 1);
  return tick % kSpectrumTickPeriod < kSpectrumTicksTaken;
}

void LiveView::watch(std::size_t node, int delta) {
  if (node < n_) watchers_[node].fetch_add(delta, std::memory_order_relaxed);
}

void LiveView::on_rx_samples(std::size_t node, SampleTime time, std::span<const cf32> samples) {
  std::lock_guard lock(spectra_mutex_);
  if (!averagers_[node]) averagers_[node] = std::make_unique<SpectrumAverager>(kSpectrumBins);
  // A periodogram block must be contiguous in time: drop a partial one at a gap.
  if (time != next_time_[node]) averagers_[node]->discard_partial_block();
  averagers_[node]->add(samples);
  next_time_[node] = time + static_cast<SampleTime>(samples.size());
}

void LiveView::publish_spectra() {
  std::lock_guard lock(spectra_mutex_);
  for (std::size_t i = 0; i < n_; ++i) {
    if (averagers_[i] && averagers_[i]->blocks() > 0) published_[i] = averagers_[i]->take_db();
  }
}

std::vector<float> LiveView::spectrum(std::size_t node) const {
  std::lock_guard lock(spectra_mutex_);
  return node < n_ ? published_[node] : std::vector<float>{};
}

void LiveView::on_decode(std::size_t node, SampleTime time, const phy::RxEvent& ev) {
  Constellation c{time, ev.tag.src, ev.tag.dst, ev.tag.serial, ev.payload_valid, {}};
  const std::size_t total = ev.symbols.size();
  const std::size_t keep = std::min(total, kMaxConstellationPoints);
  c.points.reserve(keep);
  for (std::size_t i = 0; i < keep; ++i) c.points.push_back(ev.symbols[i * total / keep]);
  std::lock_guard lock(constellation_mutex_);
  constellations_[node] = std::move(c);
}

std::optional<Constellation> LiveView::constellation(std::size_t node) const {
  std::lock_guard lock(constellation_mutex_);
  return node < n_ ? constellations_[node] : std::nullopt;
}

std::vector<std::uint8_t> LiveView::share() {
  LiveViewShare out;
  for (std::size_t i = 0; i < n_; ++i) {
    if (watchers_[i].load(std::memory_order_relaxed) > 0) {
      out.watched.push_back(static_cast<std::uint32_t>(i));
    }
  }
  {
    // The totals of the cells that changed since the last share, and every
    // tenth time of all that are not zero (so that a share a peer dropped
    // does not leave it behind for good).
    std::lock_guard lock(links_mutex_);
    const bool all = ++shares_ % 10 == 0;
    for (std::size_t k = 0; k < links_.received.size(); ++k) {
      if (links_.received[k] != shared_links_.received[k] ||
          links_.lost[k] != shared_links_.lost[k] ||
          (all && (links_.received[k] != 0 || links_.lost[k] != 0))) {
        out.links.push_back({static_cast<std::uint32_t>(k), links_.received[k], links_.lost[k]});
        shared_links_.received[k] = links_.received[k];
        shared_links_.lost[k] = links_.lost[k];
      }
    }
  }
  {
    // A node watched on another rank only: its averages are taken here (the
    // dashboard takes those of the nodes its own viewers watch).
    std::lock_guard lock(spectra_mutex_);
    for (std::size_t i = 0; i < n_; ++i) {
      if (remote_watchers_[i].load(std::memory_order_relaxed) <= 0 || !averagers_[i]) continue;
      if (averagers_[i]->blocks() > 0) published_[i] = averagers_[i]->take_db();
      if (!published_[i].empty()) {
        out.spectra.push_back({static_cast<std::uint32_t>(i), published_[i]});
      }
    }
  }
  {
    // Those of nodes watched on another rank (a viewer shows its node's only).
    std::lock_guard lock(constellation_mutex_);
    for (std::size_t i = 0; i < n_; ++i) {
      const auto& c = constellations_[i];
      if (remote_watchers_[i].load(std::memory_order_relaxed) <= 0) continue;
      if (!c || c->time <= shared_until_[i]) continue;
      shared_until_[i] = c->time;
      out.constellations.emplace_back(static_cast<std::uint32_t>(i), *c);
    }
  }
  return encode_share(out);
}

void LiveView::take_share(std::size_t rank, std::span<const std::uint8_t> bytes) {
  LiveViewShare in;
  try {
    in = decode_share(bytes, n_);
  } catch (const std::invalid_argument&) {
    bad_shares_.fetch_add(1);
    return;
  }
  // The ranks that watch each node.
  if (remote_watched_.size() <= rank) remote_watched_.resize(rank + 1);
  std::vector<std::uint32_t>& before = remote_watched_[rank];
  const auto in_list = [](const std::vector<std::uint32_t>& list, std::uint32_t node) {
    return std::find(list.begin(), list.end(), node) != list.end();
  };
  for (const std::uint32_t node : before) {
    if (!in_list(in.watched, node)) remote_watchers_[node].fetch_sub(1);
  }
  for (const std::uint32_t node : in.watched) {
    if (in_list(before, node)) continue;
    // Newly watched: its latest constellation goes out again with the next share.
    if (remote_watchers_[node].fetch_add(1) == 0) {
      std::lock_guard lock(constellation_mutex_);
      shared_until_[node] = -1;
    }
  }
  before = std::move(in.watched);
  {
    std::lock_guard lock(links_mutex_);
    if (remote_links_.size() <= rank) remote_links_.resize(rank + 1);
    LinkOutcomes& r = remote_links_[rank];
    if (r.received.empty()) {
      r.received.assign(n_ * n_, 0);
      r.lost.assign(n_ * n_, 0);
    }
    for (const auto& c : in.links) {  // totals of the cells that changed
      r.received[c.cell] = c.received;
      r.lost[c.cell] = c.lost;
    }
  }
  {
    std::lock_guard lock(spectra_mutex_);
    for (auto& sp : in.spectra) published_[sp.node] = std::move(sp.db);
  }
  std::lock_guard lock(constellation_mutex_);
  for (auto& [node, c] : in.constellations) {
    if (!constellations_[node] || constellations_[node]->time < c.time) {
      constellations_[node] = std::move(c);
    }
  }
}

}  // namespace rfsitl::monitor
