#pragma once
// Internal to the engine: typed framing. With IP on (Scenario::typed_framing)
// every radio frame's payload starts with one byte naming its FrameKind, so
// that a receiver tells an Ethernet frame from an agent's payload; without it
// the payload is the agent's bytes alone and the frame on the air is exactly
// the paper's (1704 samples for an 80-byte GMSK frame).
#include <cstdint>
#include <span>
#include <vector>

#include "rfsitl/common/net_frame.hpp"

namespace rfsitl::engine {

inline constexpr std::size_t kKindBytes = 1;

/// The bytes that go on the air for `frame`: its kind, then its payload, kept
/// in `buffer` (reused from frame to frame).
inline std::span<const std::uint8_t> with_kind(const NetFrame& frame,
                                               std::vector<std::uint8_t>& buffer) {
  buffer.resize(frame.payload.size() + kKindBytes);
  buffer[0] = static_cast<std::uint8_t>(frame.kind);
  std::copy(frame.payload.begin(), frame.payload.end(), buffer.begin() + kKindBytes);
  return buffer;
}

/// True when a decoded payload starts with a kind this build knows.
inline bool has_known_kind(std::span<const std::uint8_t> on_air) {
  return !on_air.empty() && on_air[0] <= static_cast<std::uint8_t>(FrameKind::kEthernet);
}

/// Moves the kind byte of a decoded payload into frame.kind.
/// Precondition: has_known_kind(frame.payload).
inline void strip_kind(NetFrame& frame) {
  frame.kind = static_cast<FrameKind>(frame.payload[0]);
  frame.payload.erase(frame.payload.begin());
}

}  // namespace rfsitl::engine
