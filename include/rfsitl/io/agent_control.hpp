#pragma once
/// Control frames on a net port: UB-ANC frames whose src and dst bytes are
/// both 0. No node has id 0, so a stock agent never sends one; they let a tool
/// such as `rfsitl ping` ask about a port before it uses it, without anything
/// going on the air.
///
///   request "rfsitl status" -> reply
///       "rfsitl status node=ID agent=0|1 max_payload=N nodes=LIST"
///       agent=1: another connection is this port's agent right now.
///       nodes: every node id of the run, ascending, runs of consecutive ids
///       as FIRST-LAST ("1-4,9"), so that a tool can tell a node that does not
///       exist from a port that does not answer (a 254-node run is "1-254").
///       Replies without it (older emulators) still parse.
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
#include <vector>

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
  /// Every node id of the run, ascending; empty when the reply did not say.
  std::vector<unsigned> nodes;
};

std::string format_status_reply(const PortStatus& s);

/// nullopt when `text` is not a well-formed status reply (a `nodes` list that
/// is not ascending ids 1..kMaxNodeId included). `text` is outside input (what
/// a net port sent); fuzz/agent_control_fuzzer.cpp.
std::optional<PortStatus> parse_status_reply(std::string_view text);

/// `ids` (ascending) as the reply's node list: "1-4,9"; "" for none.
std::string format_id_ranges(const std::vector<unsigned>& ids);

/// `ids` as a reader says them: "1, 2, 5" (every id, for error messages).
std::string id_list_text(const std::vector<unsigned>& ids);

}  // namespace rfsitl::io
