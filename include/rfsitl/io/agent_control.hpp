#pragma once
/// Control frames on a net port: UB-ANC frames whose src and dst bytes are
/// both 0. No node has id 0, so a stock agent never sends one; they let a tool
/// such as `rfsitl ping` ask about a port before it uses it, without anything
/// going on the air.
///
///   request "rfsitl status" -> reply "rfsitl status node=ID agent=0|1 max_payload=N"
///       agent=1: another connection is this port's agent right now.
///   request "rfsitl take"   -> reply "rfsitl taken"
///       this connection becomes the port's agent at once (the previous one is
///       closed, and the emulator logs the takeover).
///   anything else           -> reply "rfsitl error unknown request"
///
/// Control frames are answered on the connection that sent them and never
/// counted as frames handed in.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "rfsitl/common/net_frame.hpp"

namespace rfsitl::io {

inline constexpr NodeId kControlId = 0;
inline constexpr std::string_view kStatusRequest = "rfsitl status";
inline constexpr std::string_view kTakeRequest = "rfsitl take";
inline constexpr std::string_view kTakenReply = "rfsitl taken";

inline bool is_control_frame(const NetFrame& f) {
  return f.src == kControlId && f.dst == kControlId;
}

inline NetFrame make_control_frame(std::string_view text) {
  return NetFrame{kControlId, kControlId, {text.begin(), text.end()}};
}

inline std::string_view control_text(const NetFrame& f) {
  return {reinterpret_cast<const char*>(f.payload.data()), f.payload.size()};
}

/// What a status reply says about a port.
struct PortStatus {
  unsigned node = 0;
  bool agent_connected = false;
  std::size_t max_payload = 0;
};

std::string format_status_reply(const PortStatus& s);

/// nullopt when `text` is not a well-formed status reply.
std::optional<PortStatus> parse_status_reply(std::string_view text);

}  // namespace rfsitl::io
