#pragma once
/// Basic vocabulary shared by every module.
#include <complex>
#include <cstdint>

namespace rfsitl {

/// One complex baseband sample (I/Q), 32-bit float per component.
using cf32 = std::complex<float>;

/// Node identifier as carried on the wire (UB-ANC framing): 1..254. The u8
/// leaves two values over: 255 addresses every node, and 0 marks a net port's
/// control frames (rfsitl/io/agent_control.hpp).
using NodeId = std::uint8_t;

/// Destination id that addresses every node.
inline constexpr NodeId kBroadcastId = 255;
inline constexpr NodeId kMinNodeId = 1;
inline constexpr NodeId kMaxNodeId = 254;

/// Virtual time, counted in samples since the emulator started.
using SampleTime = std::int64_t;

}  // namespace rfsitl
