#include "event_reporter.hpp"

#include <cmath>

namespace rfsitl::engine {

const char* frame_event_name(FrameEventKind kind) {
  switch (kind) {
    case FrameEventKind::kHandedIn:
      return "handed_in";
    case FrameEventKind::kQueueDropped:
      return "queue_dropped";
    case FrameEventKind::kTransmitted:
      return "transmitted";
    case FrameEventKind::kReceived:
      return "received";
    case FrameEventKind::kDelivered:
      return "delivered";
    case FrameEventKind::kLost:
      return "lost";
  }
  return "unknown";
}

EventReporter::EventReporter(const scenario::Scenario& s, const channel::ChannelMatrix& channel)
    : scenario_(s), channel_(channel) {}

FrameEvent EventReporter::make(FrameEventKind kind, std::size_t sender, NodeId src, NodeId dst,
                               SampleTime t) const {
  FrameEvent e;
  e.kind = kind;
  e.time = t;
  e.src = src;
  e.dst = dst;
  e.node = scenario_.nodes[sender].id;
  const scenario::PhyChoice& phy = scenario_.phy_of(sender);
  e.phy = phy.type;
  // A PHY with a nominal data rate declares it as rate_mbps (pcap's radiotap rate).
  if (const auto* rate = phy.settings.find("rate_mbps")) {
    e.rate_mbps = static_cast<unsigned>(std::get<std::uint64_t>(*rate));
  }
  return e;
}

std::optional<std::size_t> EventReporter::receiver_of(std::size_t tx, NodeId dst) const {
  if (dst == kBroadcastId) {
    // The receiver with the best link, as the ledger names a broadcast's loss.
    std::optional<std::size_t> best;
    for (std::size_t m = 0; m < channel_.size(); ++m) {
      if (m != tx && (!best || channel_.power_gain(tx, m) > channel_.power_gain(tx, *best)))
        best = m;
    }
    return best;
  }
  for (std::size_t m = 0; m < scenario_.nodes.size(); ++m) {
    if (scenario_.nodes[m].id == dst) return m;
  }
  return std::nullopt;
}

std::optional<double> EventReporter::snr_db(std::size_t tx, std::optional<std::size_t> rx) const {
  const double noise = scenario_.channel.noise_variance;
  if (!rx || noise <= 0.0) return std::nullopt;
  const double gain = channel_.power_gain(tx, *rx);
  if (gain <= 0.0) return std::nullopt;
  return 10.0 * std::log10(gain / noise);
}

std::vector<ObserverShare> EventReporter::shares() const {
  std::vector<ObserverShare> out;
  for (EngineObserver* o : observers_) {
    if (!o->share_key().empty()) out.push_back({std::string(o->share_key()), o->share()});
  }
  return out;
}

void EventReporter::take_shares(std::size_t rank, std::span<const ObserverShare> shares) const {
  for (EngineObserver* o : observers_) {
    if (o->share_key().empty()) continue;
    for (const ObserverShare& s : shares) {
      if (s.key == o->share_key()) o->take_share(rank, s.bytes);
    }
  }
}

void EventReporter::emit(const FrameEvent& e) const {
  for (EngineObserver* o : observers_) o->on_frame_event(e);
}

void EventReporter::handed_in(std::size_t node, const NetFrame& f, SampleTime t) const {
  if (!active()) return;
  FrameEvent e = make(FrameEventKind::kHandedIn, node, f.src, f.dst, t);
  e.payload = f.payload;
  e.frame_kind = f.kind;
  emit(e);
}

void EventReporter::queue_dropped(std::size_t node, const NetFrame& f, SampleTime t) const {
  if (!active()) return;
  FrameEvent e = make(FrameEventKind::kQueueDropped, node, f.src, f.dst, t);
  e.payload = f.payload;
  e.frame_kind = f.kind;
  emit(e);
}

void EventReporter::transmitted(std::size_t node, std::uint32_t serial, const NetFrame& f,
                                SampleTime start, std::size_t length, TxRole role) {
  if (!active()) return;
  FrameEvent e = make(FrameEventKind::kTransmitted, node, f.src, f.dst, start);
  e.serial = serial;
  e.length_samples = static_cast<std::uint32_t>(length);
  e.snr_db = snr_db(node, receiver_of(node, f.dst));
  e.payload = f.payload;
  e.frame_kind = f.kind;
  e.retry = role == TxRole::kRepeat;
  emit(e);
  if (role == TxRole::kFirst) in_flight_[serial] = InFlight{f.src, f.payload, f.kind};
}

void EventReporter::received(std::size_t rx, const phy::FrameTag& tag, const NetFrame& frame,
                             SampleTime t) const {
  if (!active()) return;
  const std::size_t tx = tag.serial >> 24;  // the engine's serial carries the sender's index
  FrameEvent e = make(FrameEventKind::kReceived, tx, tag.src, tag.dst, t);
  e.node = scenario_.nodes[rx].id;
  e.serial = tag.serial;
  e.snr_db = snr_db(tx, rx);
  e.payload = frame.payload;
  e.frame_kind = frame.kind;
  emit(e);
}

void EventReporter::outcome(const LedgerOutcome& o, SampleTime now) {
  if (!active()) return;
  const auto it = in_flight_.find(o.serial);
  const NodeId src = it != in_flight_.end() ? it->second.src : scenario_.nodes[o.tx].id;
  FrameEvent e =
      make(o.delivered ? FrameEventKind::kDelivered : FrameEventKind::kLost, o.tx, src, o.dst, now);
  e.serial = o.serial;
  e.length_samples = static_cast<std::uint32_t>(o.end - o.start);
  e.reason = o.reason;
  e.snr_db = snr_db(o.tx, o.rx ? o.rx : receiver_of(o.tx, o.dst));
  if (it != in_flight_.end()) {
    e.payload = std::move(it->second.payload);
    e.frame_kind = it->second.kind;
    in_flight_.erase(it);
  }
  emit(e);
}

bool EventReporter::wants_samples(std::size_t node, SampleTime tick_start,
                                  std::size_t tick_samples) const {
  for (const EngineObserver* o : observers_) {
    if (o->wants_samples(node, tick_start, tick_samples)) return true;
  }
  return false;
}

void EventReporter::rx_samples(std::size_t node, SampleTime t,
                               std::span<const cf32> samples) const {
  for (EngineObserver* o : observers_) {
    if (o->wants_samples(node, t, samples.size())) o->on_rx_samples(node, t, samples);
  }
}

void EventReporter::retuned(std::size_t node, SampleTime t, double tx_hz, double rx_hz) const {
  for (EngineObserver* o : observers_) o->on_retune(scenario_.nodes[node].id, t, tx_hz, rx_hz);
}

void EventReporter::decoded(std::size_t node, SampleTime t, const phy::RxEvent& ev) const {
  for (EngineObserver* o : observers_) o->on_decode(node, t, ev);
}

}  // namespace rfsitl::engine
