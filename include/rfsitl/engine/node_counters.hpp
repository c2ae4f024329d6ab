#pragma once
/// Per-node accounting. Every frame an agent hands in ends in exactly one of:
/// delivered, lost (with a reason), dropped by the full TX queue; until then it
/// is pending (queued, on the air, or awaiting its receiver's verdict).
/// The reports name and describe these counters from one list:
/// node_counter_fields.hpp (a new counter needs its entry there).
#include <array>
#include <atomic>
#include <cstdint>
#include <string_view>

#include "rfsitl/mac/mac_counters.hpp"

namespace rfsitl::engine {

/// Why a transmitted frame did not reach its destination.
enum class LossReason : std::uint8_t {
  kBelowSensitivity,    ///< SNR at the receiver below the PHY's sensitivity (or no link)
  kCollision,           ///< another transmission overlapped it at the receiver
  kHalfDuplex,          ///< the receiver was transmitting during the frame
  kDecodeFailure,       ///< none of the above, yet the receiver did not decode it (CRC)
  kUnknownDestination,  ///< dst names no node of the scenario
  kRetryLimit,          ///< the MAC gave up after its retry limit, and no attempt arrived
};
inline constexpr std::size_t kNumLossReasons = 6;

std::string_view loss_reason_name(LossReason r);

/// Plain copy of a node's counters at one moment.
struct NodeCountersSnapshot {
  std::uint64_t handed_in = 0;      ///< frames the agent handed in (or the scenario injected)
  std::uint64_t queue_dropped = 0;  ///< refused because the TX queue was full
  std::uint64_t transmitted = 0;    ///< frames that went on the air
  std::uint64_t delivered = 0;      ///< own frames that reached their destination(s)
  std::array<std::uint64_t, kNumLossReasons> lost{};  ///< own frames lost, by reason
  std::uint64_t received = 0;  ///< frames this node's receiver decoded and handed to its agent
  std::uint64_t rx_crc_failures = 0;     ///< decodes at this receiver that failed the CRC
  std::uint64_t framing_errors = 0;      ///< net-port bytes rejected (oversized, too short)
  std::uint64_t ip_refused = 0;          ///< TAP frames refused (not IP/ARP, unknown MAC, > MTU)
  std::uint64_t to_agent_dropped = 0;    ///< decoded for this node but no agent connected / backlog
  std::uint64_t external_stalls = 0;     ///< round trips with the node's process that timed out
  std::uint64_t external_overflows = 0;  ///< its process's RX buffer overflowed (read too slowly)
  std::uint64_t queue_depth = 0;         ///< TX queue length (the engine's; snapshot() leaves 0)
  mac::MacCountersSnapshot mac;          ///< the node's MAC (zero for mac none)

  std::uint64_t lost_total() const {
    std::uint64_t s = 0;
    for (auto v : lost) s += v;
    return s;
  }
  /// Frames handed in that have no final outcome yet.
  std::uint64_t pending() const { return handed_in - queue_dropped - delivered - lost_total(); }
};

/// Shared between the engine and the I/O thread; every field is a relaxed atomic.
struct NodeCounters {
  std::atomic<std::uint64_t> handed_in{0};
  std::atomic<std::uint64_t> queue_dropped{0};
  std::atomic<std::uint64_t> transmitted{0};
  std::atomic<std::uint64_t> delivered{0};
  std::array<std::atomic<std::uint64_t>, kNumLossReasons> lost{};
  std::atomic<std::uint64_t> received{0};
  std::atomic<std::uint64_t> rx_crc_failures{0};
  std::atomic<std::uint64_t> framing_errors{0};
  std::atomic<std::uint64_t> ip_refused{0};
  std::atomic<std::uint64_t> to_agent_dropped{0};
  std::atomic<std::uint64_t> external_stalls{0};
  std::atomic<std::uint64_t> external_overflows{0};
  mac::MacCounters mac;

  static void bump(std::atomic<std::uint64_t>& c) { c.fetch_add(1, std::memory_order_relaxed); }
  NodeCountersSnapshot snapshot() const;
  /// Every counter set to `s`'s (a distributed run's counters of a node that
  /// another rank owns); queue_depth is not a counter and is left out.
  void assign(const NodeCountersSnapshot& s);
};

}  // namespace rfsitl::engine
