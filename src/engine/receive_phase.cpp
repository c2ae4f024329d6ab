/// LockStepEngine's RX phase: which receivers run, their inputs mixed and
/// decoded in parallel, then serially what they decoded: to the MACs, the
/// ledger's books and the agents.
#include <algorithm>

#include "lock_step_engine.hpp"

namespace rfsitl::engine {

bool LockStepEngine::receiver_must_run(std::size_t m) const {
  const Node& node = nodes_[m];
  if (blanked_whole_tick(node)) return false;
  if (!scenario_.engine.skip_idle_receivers || !air_.skipping_exact()) return true;
  return hears_more_than_noise(m);
}

bool LockStepEngine::hears_more_than_noise(std::size_t m) const {
  const Node& node = nodes_[m];
  if (node.receiver_blanked || node.radio->rx_busy()) return true;
  return air_.hears_signal(m);
}

void LockStepEngine::plan_receivers() {
  runnable_.clear();
  busy_receivers_ = 0;
  for (const std::size_t m : tx_order_) {
    Node& node = nodes_[m];
    if (!owned_[m]) {
      node.rx_tick = Node::RxTick::kElsewhere;
      continue;
    }
    node.watched = reporter_.active() && reporter_.wants_samples(m, now_, block_);
    node.tick_time = now_;
    if (node.tx_samples > 0 && !node.full_duplex) node.receiver_blanked = true;
    // Carrier sense: a node that transmits hears its own signal; whether
    // anyone else's reaches it, its input will tell (sense()).
    node.sensed_busy = node.tx_samples > 0;
    node.hears_others = node.busy_power.has_value() && air_.hears_signal(m);
    if (receiver_must_run(m)) {
      node.rx_tick = Node::RxTick::kRan;
      runnable_.push_back(m);
      if (node.radio->remote() || hears_more_than_noise(m)) ++busy_receivers_;
    } else if (node.watched && !blanked_whole_tick(node)) {
      node.rx_tick = Node::RxTick::kWatched;
      runnable_.push_back(m);
    } else {
      node.rx_tick = blanked_whole_tick(node) ? Node::RxTick::kBlanked : Node::RxTick::kSkipped;
    }
  }
}

void LockStepEngine::group_receivers() {
  rx_groups_.clear();
  const bool together = air_.mixes_together(kMixTogetherMinInputs);
  RxGroup open;
  for (const std::size_t m : runnable_) {
    if (!together || first_receive_sample(nodes_[m]) != 0) {
      rx_groups_.push_back(RxGroup{{m}, 1});
      continue;
    }
    open.receivers[open.size++] = m;
    if (open.size == open.receivers.size()) {
      rx_groups_.push_back(open);
      open.size = 0;
    }
  }
  if (open.size > 0) rx_groups_.push_back(open);
}

void LockStepEngine::rx_group(const RxGroup& group) {
  if (group.size == 1) {
    const std::size_t m = group.receivers[0];
    Node& node = nodes_[m];
    const std::size_t first = first_receive_sample(node);
    if (node.watched) std::fill_n(node.rx.begin(), first, cf32{});  // blanked: zeros
    const std::span<cf32> y(node.rx.data() + first, block_ - first);
    air_.receive(m, first, y, node.scratch);
    decode(m, y);
    sense(node, y);
    return;
  }
  std::array<cf32*, channel::Channel::kMaxTogether> ys{};
  for (std::size_t j = 0; j < group.size; ++j) ys[j] = nodes_[group.receivers[j]].rx.data();
  const std::span<const std::size_t> ms(group.receivers.data(), group.size);
  air_.receive_together(ms, {ys.data(), group.size}, nodes_[ms[0]].scratch);
  for (const std::size_t m : ms) {
    decode(m, nodes_[m].rx);
    sense(nodes_[m], nodes_[m].rx);
  }
}

void LockStepEngine::sense(Node& node, std::span<const cf32> y) {
  if (!node.busy_power || node.sensed_busy) return;
  if (node.radio->rx_busy()) {
    node.sensed_busy = true;
    return;
  }
  if (!node.hears_others || y.empty()) return;
  float power = 0.0F;
  for (const cf32 v : y) power += std::norm(v);
  node.sensed_busy = power > *node.busy_power * static_cast<float>(y.size());
}

void LockStepEngine::decode(std::size_t m, std::span<cf32> y) {
  Node& node = nodes_[m];
  if (node.rx_tick != Node::RxTick::kRan) return;
  if (node.receiver_blanked) {
    node.radio->reset_receiver();
    node.receiver_blanked = false;
  }
  node.radio->receive(y, node);
}

void LockStepEngine::handle_decodes() {
  ops_.clear();
  deliveries_.clear();
  for (std::size_t m = 0; m < nodes_.size(); ++m) {
    Node& node = nodes_[m];
    if (node.rx_tick == Node::RxTick::kElsewhere) continue;
    if (node.rx_tick == Node::RxTick::kSkipped || node.rx_tick == Node::RxTick::kWatched) {
      ++skipped_ticks_;
    }
    if (node.rx_tick == Node::RxTick::kRan) ++run_ticks_;
    if (node.rx_tick == Node::RxTick::kBlanked) ++blanked_ticks_;
    if (node.watched) {
      if (node.rx_tick == Node::RxTick::kBlanked) std::fill(node.rx.begin(), node.rx.end(), cf32{});
      reporter_.rx_samples(m, now_, node.rx);
    }
    if (node.busy_power) node.mac->on_sensed(node.sensed_busy);
    for (Decoded& d : node.decoded) classify(node, d);
    node.decoded.clear();
  }
  if (link_) link_->exchange_ops(ops_);
  for (const LedgerOp& op : ops_) replay(op);
}

void LockStepEngine::classify(Node& node, Decoded& d) {
  const auto m = static_cast<std::uint32_t>(node.index);
  // A kind byte this build does not know, or a frame too short for its
  // header, passed the CRC only if a transceiver garbled it: counted with
  // the failed decodes.
  const std::size_t header = typed_ ? kKindBytes + node.mac->header_bytes() : 0;
  if (!d.payload_valid || (typed_ && !has_known_kind(d.payload))) {
    NodeCounters::bump(counters_[m].rx_crc_failures);
    return;
  }
  if (typed_ && static_cast<FrameKind>(d.payload[0]) == FrameKind::kMacControl) {
    if (d.tag.dst != node.id) return;  // overheard
    node.mac->on_control(d.tag.src, std::span(d.payload).subspan(kKindBytes), now_);
    if (const auto v = node.mac->take_verdict()) {
      ops_.push_back({m, LedgerOp::Kind::kFrameDone, *v == mac::Verdict::kGaveUp, node.mac_frame});
    }
    return;
  }
  if (d.payload.size() < header) {
    NodeCounters::bump(counters_[m].rx_crc_failures);
    return;
  }
  // The MAC judges by what its receiver decoded (the frame's own addresses),
  // the ledger only keeps the books.
  const bool to_me = d.tag.dst == node.id;
  mac::RxDecision decision;
  if ((to_me || d.tag.dst == kBroadcastId) && d.tag.src != node.id) {
    const std::span<const std::uint8_t> mac_header =
        typed_ ? std::span<const std::uint8_t>(d.payload).subspan(kKindBytes, header - kKindBytes)
               : std::span<const std::uint8_t>();
    decision = node.mac->on_data(d.tag.src, mac_header, to_me, now_);
  }
  const std::uint32_t serial = d.tag.serial;
  deliveries_.push_back(Delivery{std::move(d), header, decision.deliver});
  ops_.push_back({m, LedgerOp::Kind::kDecoded, false, serial, deliveries_.size() - 1});
}

void LockStepEngine::replay(const LedgerOp& op) {
  if (op.kind == LedgerOp::Kind::kFrameDone) {
    ledger_->on_frame_done(op.id, op.gave_up);
    return;
  }
  defer_outcomes_ = true;
  const bool for_this_node = ledger_->on_decoded(op.id, op.node);
  defer_outcomes_ = false;
  if (op.delivery != LedgerOp::kNoDelivery && for_this_node && deliveries_[op.delivery].deliver) {
    Delivery& delivery = deliveries_[op.delivery];
    Decoded& d = delivery.decoded;
    NodeCounters::bump(counters_[op.node].received);
    NetFrame frame{d.tag.src, d.tag.dst, std::move(d.payload)};
    if (typed_) strip_header(frame, delivery.header);
    reporter_.received(op.node, d.tag, frame, now_);
    sink_.deliver(op.node, std::move(frame));
  }
  for (const LedgerOutcome& o : deferred_outcomes_) reporter_.outcome(o, now_);
  deferred_outcomes_.clear();
}

}  // namespace rfsitl::engine
