#include "node_tx_report.hpp"

#include <algorithm>

namespace rfsitl::engine {

bool has_tx_report(const Node& node) {
  return node.active || node.verdict || node.started;
}

TxReport tx_report_of(const Node& node) {
  TxReport t;
  t.node = static_cast<std::uint32_t>(node.index);
  t.tx_samples = static_cast<std::uint32_t>(node.tx_samples);
  if (node.verdict) {
    t.has_verdict = true;
    t.verdict_frame = node.verdict->frame;
    t.gave_up = node.verdict->verdict == mac::Verdict::kGaveUp;
  }
  if (node.started) {
    t.started = true;
    t.serial = node.started->first;
    t.dst = node.started->second.dst;
    t.kind = static_cast<std::uint8_t>(node.started->second.kind);
    t.started_len = static_cast<std::uint32_t>(node.started_len);
    t.awaits_verdict = node.started_awaits_verdict;
    t.first_attempt = node.started_first_attempt;
    t.mac_frame = node.mac_frame;
  }
  return t;
}

void take_tx_report(Node& node, const TxReport& t) {
  node.tx_samples = t.tx_samples;
  node.active = t.tx_samples > 0;
  // The owner's transceiver left zeros after its signal (tx_samples).
  std::fill(node.tx.begin() + t.tx_samples, node.tx.end(), cf32{});
  if (t.has_verdict) {
    node.verdict = PendingVerdict{t.verdict_frame,
                                  t.gave_up ? mac::Verdict::kGaveUp : mac::Verdict::kAcknowledged};
  }
  if (t.started) {
    node.started_len = t.started_len;
    node.started_awaits_verdict = t.awaits_verdict;
    node.started_first_attempt = t.first_attempt;
    node.mac_frame = t.mac_frame;
    NetFrame frame{node.id, t.dst, {}, static_cast<FrameKind>(t.kind)};
    node.started.emplace(t.serial, std::move(frame));
  }
}

}  // namespace rfsitl::engine
