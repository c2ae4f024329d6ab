#pragma once
/// One step in a frame's life, as traces and the dashboard see it.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "rfsitl/common/net_frame.hpp"
#include "rfsitl/common/types.hpp"
#include "rfsitl/engine/node_counters.hpp"

namespace rfsitl::engine {

enum class FrameEventKind : std::uint8_t {
  kHandedIn,      ///< the agent handed it to its net port (or the scenario injected it)
  kQueueDropped,  ///< refused: the TX queue was full (final)
  kTransmitted,   ///< went on the air at `time` for `length_samples`
  kReceived,      ///< `node`'s receiver decoded it and handed it to its agent
  kDelivered,     ///< reached its destination (for broadcast: some node) (final)
  kLost,          ///< nobody it was meant for decoded it; `reason` says why (final)
};

const char* frame_event_name(FrameEventKind kind);

struct FrameEvent {
  FrameEventKind kind = FrameEventKind::kHandedIn;
  SampleTime time = 0;  ///< virtual time, samples since the start (fs in the run's settings)
  NodeId src = 0;
  NodeId dst = 0;
  /// Where it happened: the sender (handed in, dropped, transmitted,
  /// delivered, lost) or the receiver (received).
  NodeId node = 0;
  std::uint32_t serial = 0;          ///< per transmission; 0 before it is transmitted
  std::uint32_t length_samples = 0;  ///< air time (transmitted, delivered, lost)
  std::optional<LossReason> reason;  ///< kLost only
  /// Signal power over noise at the receiver in question (dst; for broadcasts
  /// the receiver with the best link), from the channel at the event; nullopt
  /// when there is no such receiver or no noise.
  std::optional<double> snr_db;
  std::string phy;                    ///< the sender's PHY type ("gmsk", "ofdm", ...)
  unsigned rate_mbps = 0;             ///< the sender PHY's rate_mbps setting (ofdm); 0: none
  std::vector<std::uint8_t> payload;  ///< the net frame's payload (without src/dst)
  /// What the payload is: an agent's bytes, or (IP on) an Ethernet frame.
  FrameKind frame_kind = FrameKind::kAgent;
  /// kTransmitted: a repeat of a frame already sent (the MAC's retry).
  bool retry = false;
};

}  // namespace rfsitl::engine
