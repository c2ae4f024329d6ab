#pragma once
/// A packet as an agent hands it to its net port (or an IP node's TAP
/// interface): source, destination, payload, and what kind of packet it is.
#include <cstdint>
#include <vector>

#include "rfsitl/common/types.hpp"

namespace rfsitl {

/// What a frame carries. The kind travels on the air (one byte before the
/// payload) only with typed framing, i.e. when IP or a MAC is on; otherwise
/// every frame is kAgent and the frame on the air is exactly the paper's.
enum class FrameKind : std::uint8_t {
  kAgent = 0,       ///< an agent's payload from its net port (UB-ANC framing)
  kEthernet = 1,    ///< an Ethernet frame from the node's TAP interface (IPv4, IPv6, ARP)
  kMacControl = 2,  ///< the MAC's own frame (an ACK): never handed in, never delivered
};

struct NetFrame {
  NodeId src = 0;
  NodeId dst = 0;
  std::vector<std::uint8_t> payload;
  FrameKind kind = FrameKind::kAgent;

  friend bool operator==(const NetFrame&, const NetFrame&) = default;
};

}  // namespace rfsitl
