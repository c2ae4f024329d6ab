#include "rfsitl/engine/frame_ledger.hpp"

#include <algorithm>
#include <cmath>

#include "rfsitl/engine/node_counter_fields.hpp"

namespace rfsitl::engine {

std::string_view loss_reason_name(LossReason r) {
  const auto i = static_cast<std::size_t>(r);
  return i < kLossReasons.size() ? kLossReasons[i].key : "?";
}

NodeCountersSnapshot NodeCounters::snapshot() const {
  // Outcomes are read before handed_in so that a concurrent snapshot never shows
  // more outcomes than frames (pending() cannot underflow).
  NodeCountersSnapshot s;
  for (const NodeCounterField& f : kNodeCounterFields) {
    if (f.outcome) f.access.load(*this, s);
  }
  std::atomic_thread_fence(std::memory_order_acquire);
  for (const NodeCounterField& f : kNodeCounterFields) {
    if (!f.outcome && f.access.stored) f.access.load(*this, s);
  }
  return s;
}

void NodeCounters::assign(const NodeCountersSnapshot& s) {
  for (const NodeCounterField& f : kNodeCounterFields) {
    if (f.access.stored) f.access.store(*this, s);
  }
}

FrameLedger::FrameLedger(LedgerConfig config, std::span<NodeCounters> counters,
                         std::function<std::optional<std::size_t>(NodeId)> index_of_id)
    : config_(config), counters_(counters), index_of_id_(std::move(index_of_id)) {}

void FrameLedger::on_transmit(std::uint32_t serial, std::size_t tx, NodeId dst, SampleTime start,
                              SampleTime end, std::uint32_t frame) {
  records_.push_back(Record{serial, tx, dst, start, end, 0, false, false, frame});
  longest_frame_ = std::max(longest_frame_, end - start);
  NodeCounters::bump(counters_[tx].transmitted);
  if (frame != 0) {
    AttemptedFrame& f = attempted_[frame];
    ++f.unsettled;
    f.last = records_.back();
  }
}

void FrameLedger::on_frame_done(std::uint32_t frame, bool gave_up) {
  const auto it = attempted_.find(frame);
  if (it == attempted_.end()) return;
  it->second.done = true;
  it->second.gave_up = gave_up;
  resolve_if_done(frame);
}

void FrameLedger::resolve_if_done(std::uint32_t frame) {
  const auto it = attempted_.find(frame);
  AttemptedFrame& f = it->second;
  if (!f.done || f.unsettled > 0) return;
  if (!f.delivered) {
    // Giving up names the MAC; the physical reason of each attempt is in the
    // trace's per-attempt events and the MAC's counters.
    const LossReason why = f.gave_up ? LossReason::kRetryLimit : f.last_reason;
    NodeCounters::bump(counters_[f.last.tx].lost[static_cast<std::size_t>(why)]);
    Record as_frame = f.last;
    as_frame.serial = frame;
    report(as_frame, false, f.rx, why);
  }
  attempted_.erase(it);
}

void FrameLedger::on_activity(std::size_t tx, SampleTime start, SampleTime end) {
  for (auto it = records_.rbegin(); it != records_.rend(); ++it) {
    if (it->activity && it->tx == tx && it->end == start) {
      it->end = end;
      return;
    }
  }
  records_.push_back(Record{0, tx, 0, start, end, 0, true, true});
}

bool FrameLedger::on_decoded(std::uint32_t serial, std::size_t rx) {
  auto it = std::find_if(records_.begin(), records_.end(),
                         [&](const Record& r) { return !r.activity && r.serial == serial; });
  if (it == records_.end() || it->tx == rx) return false;
  Record& r = *it;
  const bool broadcast = r.dst == kBroadcastId;
  const auto dst_index = broadcast ? std::nullopt : index_of_id_(r.dst);
  if (!broadcast && dst_index != rx) return false;
  if (r.settled) {
    // Decoded after its verdict was due: it was counted lost; keep the books
    // consistent and do not deliver it (grace_samples is meant to make this rare).
    ++late_decodes_;
    return false;
  }
  ++r.decodes;
  if (r.frame != 0) {
    // An attempt: the frame is delivered by the first attempt its destination
    // decodes; a repeat decoded later is the MAC's duplicate, not counted.
    r.settled = true;
    AttemptedFrame& f = attempted_.at(r.frame);
    --f.unsettled;
    if (!f.delivered) {
      f.delivered = true;
      NodeCounters::bump(counters_[r.tx].delivered);
      Record as_frame = r;
      as_frame.serial = r.frame;
      report(as_frame, true, rx, std::nullopt);
    }
    resolve_if_done(r.frame);
    return true;
  }
  // A unicast frame is settled by its one decode; a broadcast waits for every
  // receiver's verdict and counts as delivered if any receiver decoded it.
  if (!broadcast) {
    r.settled = true;
    NodeCounters::bump(counters_[r.tx].delivered);
    report(r, true, rx, std::nullopt);
  }
  return true;
}

LossReason FrameLedger::loss_reason(const Record& r, std::size_t rx,
                                    const channel::ChannelMatrix& channel) const {
  const auto overlaps = [&](const Record& o) { return o.start < r.end && r.start < o.end; };
  const bool full_duplex = rx < config_.full_duplex.size() && config_.full_duplex[rx];
  for (const Record& o : records_) {
    if (o.tx == rx && overlaps(o) && !full_duplex) return LossReason::kHalfDuplex;
  }
  const double noise = config_.noise_variance;
  const double signal = channel.power_gain(r.tx, rx);
  const double snr_db = signal <= 0.0  ? -INFINITY
                        : noise <= 0.0 ? INFINITY
                                       : 10.0 * std::log10(signal / noise);
  if (snr_db < config_.sensitivity_snr_db[r.tx]) return LossReason::kBelowSensitivity;
  for (const Record& o : records_) {
    // An overlapping transmission counts as a collision when it reaches the
    // receiver at least as strong as the noise floor.
    if (&o != &r && o.tx != r.tx && overlaps(o) && channel.power_gain(o.tx, rx) >= noise &&
        channel.power_gain(o.tx, rx) > 0.0F) {
      return LossReason::kCollision;
    }
  }
  return LossReason::kDecodeFailure;
}

void FrameLedger::settle_record(Record& r, const channel::ChannelMatrix& channel) {
  r.settled = true;
  NodeCounters& c = counters_[r.tx];
  if (r.dst == kBroadcastId) {
    if (r.decodes > 0) {
      NodeCounters::bump(c.delivered);
      report(r, true, std::nullopt, std::nullopt);
      return;
    }
    // Nobody decoded it: name the reason at the receiver with the best link.
    std::optional<std::size_t> best;
    for (std::size_t m = 0; m < channel.size(); ++m) {
      if (m == r.tx) continue;
      if (!best || channel.power_gain(r.tx, m) > channel.power_gain(r.tx, *best)) best = m;
    }
    // A lone node's broadcast has no link to anyone: below sensitivity, as for
    // a receiver without a position (its destination, "everyone", is known).
    const LossReason why = best ? loss_reason(r, *best, channel) : LossReason::kBelowSensitivity;
    NodeCounters::bump(c.lost[static_cast<std::size_t>(why)]);
    report(r, false, best, why);
    return;
  }
  const auto rx = index_of_id_(r.dst);
  const LossReason why = rx ? loss_reason(r, *rx, channel) : LossReason::kUnknownDestination;
  if (r.frame != 0) {
    // One attempt failed; the frame is counted when the MAC is done with it.
    AttemptedFrame& f = attempted_.at(r.frame);
    f.last_reason = why;
    f.rx = rx;
    --f.unsettled;
    resolve_if_done(r.frame);
    return;
  }
  NodeCounters::bump(c.lost[static_cast<std::size_t>(why)]);
  report(r, false, rx, why);
}

void FrameLedger::report(const Record& r, bool delivered, std::optional<std::size_t> rx,
                         std::optional<LossReason> reason) const {
  if (on_outcome_)
    on_outcome_(LedgerOutcome{delivered, r.serial, r.tx, r.dst, rx, reason, r.start, r.end});
}

void FrameLedger::settle(SampleTime now, const channel::ChannelMatrix& channel) {
  // A delayed path brings a frame's end to its receivers up to max_lag() later.
  const SampleTime grace = config_.grace_samples + static_cast<SampleTime>(channel.max_lag());
  for (Record& r : records_) {
    if (!r.settled && r.end + grace <= now) settle_record(r, channel);
  }
  // A settled record is still needed while a frame it overlaps may await its verdict.
  const SampleTime horizon = now - 2 * (longest_frame_ + grace);
  std::erase_if(records_, [&](const Record& r) { return r.settled && r.end < horizon; });
}

std::size_t FrameLedger::in_flight() const {
  return static_cast<std::size_t>(
      std::count_if(records_.begin(), records_.end(), [](const Record& r) { return !r.settled; }));
}

}  // namespace rfsitl::engine
