#pragma once
/// What a node's MAC counts. Written by the engine thread (the MAC's), read by
/// any thread (reports); every field is a relaxed atomic. Header-only, so that
/// the engine's counters hold it without linking the MACs. The node's counter
/// table (engine/node_counter_fields.hpp) names each and copies it.
#include <atomic>
#include <cstdint>

namespace rfsitl::mac {

/// Plain copy of a node's MAC counters at one moment.
struct MacCountersSnapshot {
  std::uint64_t retries = 0;        ///< transmissions that repeated a frame (after an ACK timeout)
  std::uint64_t ack_timeouts = 0;   ///< unicast transmissions whose ACK did not come in time
  std::uint64_t retry_drops = 0;    ///< frames abandoned after the retry limit
  std::uint64_t duplicates = 0;     ///< received frames dropped as repeats (same sequence number)
  std::uint64_t control_sent = 0;   ///< MAC control frames (ACKs) transmitted
  std::uint64_t backoff_slots = 0;  ///< backoff slots counted down
  std::uint64_t busy_ticks = 0;     ///< ticks in which carrier sense found the channel busy
  std::uint64_t sensed_ticks = 0;   ///< ticks carrier sense looked at the channel
};

struct MacCounters {
  std::atomic<std::uint64_t> retries{0};
  std::atomic<std::uint64_t> ack_timeouts{0};
  std::atomic<std::uint64_t> retry_drops{0};
  std::atomic<std::uint64_t> duplicates{0};
  std::atomic<std::uint64_t> control_sent{0};
  std::atomic<std::uint64_t> backoff_slots{0};
  std::atomic<std::uint64_t> busy_ticks{0};
  std::atomic<std::uint64_t> sensed_ticks{0};

  static void bump(std::atomic<std::uint64_t>& c, std::uint64_t by = 1) {
    c.fetch_add(by, std::memory_order_relaxed);
  }
};

}  // namespace rfsitl::mac
