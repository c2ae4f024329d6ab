#include "rfsitl/monitor/live_view.hpp"

#include <algorithm>

namespace rfsitl::monitor {

LiveView::LiveView(std::vector<NodeId> ids)
    : ids_(std::move(ids)),
      n_(ids_.size()),
      watchers_(new std::atomic<int>[n_]),
      averagers_(n_),
      published_(n_),
      next_time_(n_, -1),
      constellations_(n_) {
  links_.received.assign(n_ * n_, 0);
  links_.lost.assign(n_ * n_, 0);
  for (std::size_t i = 0; i < n_; ++i) watchers_[i].store(0);
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
  return links_;
}

bool LiveView::wants_samples(std::size_t node, SampleTime tick_start,
                             std::size_t tick_samples) const {
  if (node >= n_ || watchers_[node].load(std::memory_order_relaxed) <= 0) return false;
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

}  // namespace rfsitl::monitor
