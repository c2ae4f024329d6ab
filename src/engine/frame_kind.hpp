#pragma once
// Internal to the engine: typed framing. With IP or a MAC on
// (Scenario::typed_framing) every radio frame's payload starts with one byte
// naming its FrameKind, then the MAC's header, so that a receiver tells an
// Ethernet frame from an agent's payload and from the MAC's own frames;
// without it the payload is the agent's bytes alone and the frame on the air
// is exactly the paper's (1704 samples for an 80-byte GMSK frame).
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "rfsitl/common/net_frame.hpp"

namespace rfsitl::engine {

inline constexpr std::size_t kKindBytes = 1;

/// The bytes that go on the air: `kind`, the MAC `header`, then `payload`,
/// kept in `buffer` (reused from frame to frame).
inline std::span<const std::uint8_t> with_kind(FrameKind kind, std::span<const std::uint8_t> header,
                                               std::span<const std::uint8_t> payload,
                                               std::vector<std::uint8_t>& buffer) {
  buffer.resize(kKindBytes + header.size() + payload.size());
  buffer[0] = static_cast<std::uint8_t>(kind);
  std::copy(header.begin(), header.end(), buffer.begin() + kKindBytes);
  std::copy(payload.begin(), payload.end(),
            buffer.begin() + static_cast<std::ptrdiff_t>(kKindBytes + header.size()));
  return buffer;
}

/// True when a decoded payload starts with a kind this build knows.
inline bool has_known_kind(std::span<const std::uint8_t> on_air) {
  return !on_air.empty() && on_air[0] <= static_cast<std::uint8_t>(FrameKind::kMacControl);
}

/// Moves the kind byte of a decoded payload into frame.kind and drops it and
/// the MAC header (`header` bytes in all). Precondition: has_known_kind() and
/// frame.payload.size() >= header >= kKindBytes.
inline void strip_header(NetFrame& frame, std::size_t header) {
  frame.kind = static_cast<FrameKind>(frame.payload[0]);
  frame.payload.erase(frame.payload.begin(),
                      frame.payload.begin() + static_cast<std::ptrdiff_t>(header));
}

}  // namespace rfsitl::engine
