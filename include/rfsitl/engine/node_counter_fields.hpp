#pragma once
/// The per-node counters, each declared once with its names and meaning. Every
/// report iterates this list: the summary JSON and /api/stats (`key`), /metrics
/// (`metric`, `help`, `kind`), the end-of-run table (`column`) and the
/// dashboard's table (`label`, `help`, sent in the hello message), and
/// NodeCounters::snapshot() and assign() (`access`). A new counter is its
/// atomic in NodeCounters, its number in NodeCountersSnapshot, and one entry
/// here naming both (a static_assert below catches a forgotten entry).
#include <array>
#include <cstdint>
#include <string_view>

#include "rfsitl/engine/node_counters.hpp"

namespace rfsitl::engine {

/// How a loss reason is named: `key` in JSON and the `reason` metric label,
/// `column` after "lost:" in the end-of-run table, `label` and `help` on the dashboard.
struct LossReasonInfo {
  LossReason reason;
  std::string_view key;
  std::string_view column;
  std::string_view label;
  std::string_view help;
};

/// Indexed by LossReason (NodeCountersSnapshot::lost is too).
inline constexpr std::array<LossReasonInfo, kNumLossReasons> kLossReasons{{
    {LossReason::kBelowSensitivity, "below_sensitivity", "sen", "below sens.",
     "SNR at the receiver below the PHY's sensitivity (or no link)"},
    {LossReason::kCollision, "collision", "col", "collision",
     "Another transmission overlapped it at the receiver"},
    {LossReason::kHalfDuplex, "half_duplex", "hd", "half-duplex",
     "The receiver was transmitting during the frame"},
    {LossReason::kDecodeFailure, "decode_failure", "dec", "decode fail",
     "None of the above, yet the receiver did not decode it (CRC)"},
    {LossReason::kUnknownDestination, "unknown_destination", "dst", "unknown dst",
     "The destination names no node of the scenario"},
    {LossReason::kRetryLimit, "retry_limit", "retry", "retry limit",
     "The MAC gave up after its retry limit, and none of the attempts arrived"},
}};

/// Prometheus metric type: a counter only grows, a gauge goes up and down.
enum class CounterKind : std::uint8_t { kCounter, kGauge };

constexpr std::string_view counter_kind_name(CounterKind k) {
  return k == CounterKind::kGauge ? "gauge" : "counter";
}

/// A stored counter's (or array's) value, read or written relaxed.
inline void load_into(const std::atomic<std::uint64_t>& a, std::uint64_t& v) {
  v = a.load(std::memory_order_relaxed);
}
inline void store_from(std::atomic<std::uint64_t>& a, std::uint64_t v) {
  a.store(v, std::memory_order_relaxed);
}
template <std::size_t N>
void load_into(const std::array<std::atomic<std::uint64_t>, N>& a,
               std::array<std::uint64_t, N>& v) {
  for (std::size_t i = 0; i < N; ++i) load_into(a[i], v[i]);
}
template <std::size_t N>
void store_from(std::array<std::atomic<std::uint64_t>, N>& a,
                const std::array<std::uint64_t, N>& v) {
  for (std::size_t i = 0; i < N; ++i) store_from(a[i], v[i]);
}

/// How a stored counter moves between NodeCounters (atomics) and its
/// snapshot: the table below drives NodeCounters::snapshot() and assign().
/// Both null for a field that is not stored (pending, derived; queue_depth,
/// the engine's).
struct CounterAccess {
  void (*load)(const NodeCounters&, NodeCountersSnapshot&) = nullptr;
  void (*store)(NodeCounters&, const NodeCountersSnapshot&) = nullptr;
  bool stored = false;  ///< load and store are set (a lambda's pointer is not a constant)
};

/// The access of a counter stored as NodeCounters::*A, snapshot as
/// NodeCountersSnapshot::*V (an atomic and a number, or arrays of them).
template <auto A, auto V>
constexpr CounterAccess stored() {
  return {[](const NodeCounters& c, NodeCountersSnapshot& s) { load_into(c.*A, s.*V); },
          [](NodeCounters& c, const NodeCountersSnapshot& s) { store_from(c.*A, s.*V); }, true};
}

/// The same for a counter of the node's MAC (NodeCounters::mac).
template <auto A, auto V>
constexpr CounterAccess stored_mac() {
  return {[](const NodeCounters& c, NodeCountersSnapshot& s) { load_into(c.mac.*A, s.mac.*V); },
          [](NodeCounters& c, const NodeCountersSnapshot& s) { store_from(c.mac.*A, s.mac.*V); },
          true};
}

/// One per-node number. A field with `by_reason` is one number per loss reason
/// (a JSON object keyed by reason, a `reason` label, a column per reason);
/// `read` then gives their total.
struct NodeCounterField {
  std::string_view key;     ///< JSON key of nodes[i]; the dashboard cell's class
  std::string_view metric;  ///< Prometheus family, labelled {node="ID"}
  CounterKind kind;
  std::string_view help;    ///< one line: Prometheus HELP and the dashboard's tooltip
  std::string_view label;   ///< dashboard column header
  std::string_view column;  ///< end-of-run table header (short: the terminal is narrow)
  std::uint64_t (*read)(const NodeCountersSnapshot&);
  std::array<std::uint64_t, kNumLossReasons> NodeCountersSnapshot::*by_reason = nullptr;
  /// The end-of-run table leaves the column out while every node has 0 (the
  /// MAC's counters in a run without one).
  bool table_hides_zero = false;
  CounterAccess access{};  ///< where it is stored; null for derived numbers
  /// A frame's final outcome: snapshot() reads these before handed_in, so that
  /// a snapshot never shows more outcomes than frames (pending() >= 0).
  bool outcome = false;
};

/// A field's reader from its member (a function pointer keeps the table constexpr
/// and lets derived numbers such as pending() sit next to stored ones).
template <std::uint64_t NodeCountersSnapshot::*Member>
constexpr std::uint64_t read_member(const NodeCountersSnapshot& s) {
  return s.*Member;
}

/// The order of the reports' columns and metric families.
inline constexpr std::array kNodeCounterFields{
    NodeCounterField{"handed_in", "rfsitl_frames_handed_in_total", CounterKind::kCounter,
                     "Frames the agent handed in.", "handed in", "in",
                     read_member<&NodeCountersSnapshot::handed_in>, nullptr, false,
                     stored<&NodeCounters::handed_in, &NodeCountersSnapshot::handed_in>()},
    NodeCounterField{"transmitted", "rfsitl_frames_transmitted_total", CounterKind::kCounter,
                     "Frames that went on the air.", "transmitted", "tx",
                     read_member<&NodeCountersSnapshot::transmitted>, nullptr, false,
                     stored<&NodeCounters::transmitted, &NodeCountersSnapshot::transmitted>()},
    NodeCounterField{
        "delivered", "rfsitl_frames_delivered_total", CounterKind::kCounter,
        "Own frames that reached their destination: decoded by its receiver (whether its agent "
        "took them is the destination's to-agent-drop).",
        "delivered", "delivered", read_member<&NodeCountersSnapshot::delivered>, nullptr, false,
        stored<&NodeCounters::delivered, &NodeCountersSnapshot::delivered>(), true},
    NodeCounterField{"lost", "rfsitl_frames_lost_total", CounterKind::kCounter,
                     "Own frames lost on the air, by reason.", "lost (own frames)", "lost",
                     [](const NodeCountersSnapshot& s) { return s.lost_total(); },
                     &NodeCountersSnapshot::lost, false,
                     stored<&NodeCounters::lost, &NodeCountersSnapshot::lost>(), true},
    NodeCounterField{"queue_dropped", "rfsitl_frames_queue_dropped_total", CounterKind::kCounter,
                     "Frames refused by the full TX queue.", "queue dropped", "q-drop",
                     read_member<&NodeCountersSnapshot::queue_dropped>, nullptr, false,
                     stored<&NodeCounters::queue_dropped, &NodeCountersSnapshot::queue_dropped>(),
                     true},
    NodeCounterField{
        "pending", "rfsitl_frames_pending", CounterKind::kGauge,
        "Frames handed in without a final outcome yet (queued, on the air, being decoded).",
        "pending", "pending", [](const NodeCountersSnapshot& s) { return s.pending(); }},
    NodeCounterField{"received", "rfsitl_frames_received_total", CounterKind::kCounter,
                     "Frames decoded and handed to the agent.", "received", "received",
                     read_member<&NodeCountersSnapshot::received>, nullptr, false,
                     stored<&NodeCounters::received, &NodeCountersSnapshot::received>()},
    NodeCounterField{
        "rx_crc_failures", "rfsitl_rx_crc_failures_total", CounterKind::kCounter,
        "Decodes that failed the CRC.", "CRC failures", "crc-fail",
        read_member<&NodeCountersSnapshot::rx_crc_failures>, nullptr, false,
        stored<&NodeCounters::rx_crc_failures, &NodeCountersSnapshot::rx_crc_failures>()},
    NodeCounterField{
        "to_agent_dropped", "rfsitl_frames_to_agent_dropped_total", CounterKind::kCounter,
        "Frames decoded for the node but not handed to its agent (none connected, backlog); "
        "their senders count them as delivered: the radio link worked.",
        "to agent dropped", "to-agent-drop", read_member<&NodeCountersSnapshot::to_agent_dropped>,
        nullptr, false,
        stored<&NodeCounters::to_agent_dropped, &NodeCountersSnapshot::to_agent_dropped>()},
    NodeCounterField{
        "framing_errors", "rfsitl_framing_errors_total", CounterKind::kCounter,
        "Net-port frames refused (oversized or too short).", "framing errors", "frame-err",
        read_member<&NodeCountersSnapshot::framing_errors>, nullptr, false,
        stored<&NodeCounters::framing_errors, &NodeCountersSnapshot::framing_errors>()},
    NodeCounterField{"ip_refused", "rfsitl_ip_frames_refused_total", CounterKind::kCounter,
                     "Frames from the node's TAP interface refused: not IPv4, IPv6 or ARP, a "
                     "destination MAC that names no node, or longer than the MTU.",
                     "IP refused", "ip-ref", read_member<&NodeCountersSnapshot::ip_refused>,
                     nullptr, false,
                     stored<&NodeCounters::ip_refused, &NodeCountersSnapshot::ip_refused>()},
    NodeCounterField{"queue_depth", "rfsitl_tx_queue_depth", CounterKind::kGauge,
                     "Frames waiting in the TX queue.", "queue depth", "q-depth",
                     read_member<&NodeCountersSnapshot::queue_depth>},
    NodeCounterField{
        "external_stalls", "rfsitl_external_stalls_total", CounterKind::kCounter,
        "Replies the node's external process owed but did not send within "
        "external.reply_timeout_s; the whole engine waited that long each time.",
        "ext. stalls", "stalls", read_member<&NodeCountersSnapshot::external_stalls>, nullptr,
        false, stored<&NodeCounters::external_stalls, &NodeCountersSnapshot::external_stalls>()},
    NodeCounterField{
        "external_overflows", "rfsitl_external_overflows_total", CounterKind::kCounter,
        "Overflows the node's external process reported: times its RX buffer "
        "dropped samples because the application read too slowly (a SoapySDR "
        "application's SOAPY_SDR_OVERFLOW).",
        "ext. overflows", "ovfl", read_member<&NodeCountersSnapshot::external_overflows>, nullptr,
        true,
        stored<&NodeCounters::external_overflows, &NodeCountersSnapshot::external_overflows>()},
    // The MAC's (zero with mac none).
    NodeCounterField{"mac_retries", "rfsitl_mac_retries_total", CounterKind::kCounter,
                     "Transmissions that repeated a unicast frame after its ACK timed out.",
                     "MAC retries", "retry",
                     [](const NodeCountersSnapshot& s) { return s.mac.retries; }, nullptr, true,
                     stored_mac<&mac::MacCounters::retries, &mac::MacCountersSnapshot::retries>()},
    NodeCounterField{
        "mac_ack_timeouts", "rfsitl_mac_ack_timeouts_total", CounterKind::kCounter,
        "Unicast transmissions whose ACK did not come in time.", "ACK timeouts", "ack-to",
        [](const NodeCountersSnapshot& s) { return s.mac.ack_timeouts; }, nullptr, true,
        stored_mac<&mac::MacCounters::ack_timeouts, &mac::MacCountersSnapshot::ack_timeouts>()},
    NodeCounterField{
        "mac_retry_drops", "rfsitl_mac_retry_drops_total", CounterKind::kCounter,
        "Frames the MAC gave up after its retry limit (lost: retry_limit unless "
        "an attempt arrived and only its ACKs were lost).",
        "retry-limit drops", "rl-drop",
        [](const NodeCountersSnapshot& s) { return s.mac.retry_drops; }, nullptr, true,
        stored_mac<&mac::MacCounters::retry_drops, &mac::MacCountersSnapshot::retry_drops>()},
    NodeCounterField{
        "mac_duplicates", "rfsitl_mac_duplicates_total", CounterKind::kCounter,
        "Received repeats of a frame already delivered, dropped by sequence number.", "duplicates",
        "dup", [](const NodeCountersSnapshot& s) { return s.mac.duplicates; }, nullptr, true,
        stored_mac<&mac::MacCounters::duplicates, &mac::MacCountersSnapshot::duplicates>()},
    NodeCounterField{
        "mac_control_sent", "rfsitl_mac_control_frames_total", CounterKind::kCounter,
        "MAC control frames (ACKs) transmitted; never counted as handed in.", "ACKs sent", "ctl",
        [](const NodeCountersSnapshot& s) { return s.mac.control_sent; }, nullptr, true,
        stored_mac<&mac::MacCounters::control_sent, &mac::MacCountersSnapshot::control_sent>()},
    NodeCounterField{
        "mac_backoff_slots", "rfsitl_mac_backoff_slots_total", CounterKind::kCounter,
        "Backoff slots counted down (times the slot length: time spent in backoff).",
        "backoff slots", "backoff",
        [](const NodeCountersSnapshot& s) { return s.mac.backoff_slots; }, nullptr, true,
        stored_mac<&mac::MacCounters::backoff_slots, &mac::MacCountersSnapshot::backoff_slots>()},
    NodeCounterField{
        "mac_busy_ticks", "rfsitl_mac_busy_ticks_total", CounterKind::kCounter,
        "Ticks in which carrier sense found the channel busy (over "
        "mac_sensed_ticks: the channel-busy fraction).",
        "busy ticks", "busy", [](const NodeCountersSnapshot& s) { return s.mac.busy_ticks; },
        nullptr, true,
        stored_mac<&mac::MacCounters::busy_ticks, &mac::MacCountersSnapshot::busy_ticks>()},
    NodeCounterField{
        "mac_sensed_ticks", "rfsitl_mac_sensed_ticks_total", CounterKind::kCounter,
        "Ticks in which carrier sense looked at the channel.", "sensed ticks", "sensed",
        [](const NodeCountersSnapshot& s) { return s.mac.sensed_ticks; }, nullptr, true,
        stored_mac<&mac::MacCounters::sensed_ticks, &mac::MacCountersSnapshot::sensed_ticks>()},
};

namespace detail {
constexpr bool loss_reasons_in_enum_order() {
  for (std::size_t r = 0; r < kLossReasons.size(); ++r) {
    if (static_cast<std::size_t>(kLossReasons[r].reason) != r) return false;
  }
  return true;
}
}  // namespace detail
static_assert(detail::loss_reasons_in_enum_order(), "kLossReasons is indexed by LossReason");

namespace detail {
/// The numbers the table stores (a by-reason field is one per reason).
constexpr std::size_t stored_numbers() {
  std::size_t n = 0;
  for (const NodeCounterField& f : kNodeCounterFields) {
    if (f.access.stored) n += f.by_reason != nullptr ? kNumLossReasons : 1;
  }
  return n;
}
}  // namespace detail
// Every number of the snapshot but queue_depth (the engine's) is a stored
// counter with its entry above: a field added to the structs alone fails here.
static_assert(detail::stored_numbers() + 1 == sizeof(NodeCountersSnapshot) / sizeof(std::uint64_t),
              "a counter of NodeCountersSnapshot has no entry in kNodeCounterFields");

}  // namespace rfsitl::engine
