#pragma once
/// Who may steer the run from the dashboard. With `--dashboard-control` a viewer
/// can move nodes; on a loopback address only this machine's users can reach
/// the dashboard, but bound to another address anyone on that network could.
/// There, control requests (a WebSocket "move", POST /api/nodes/ID/position)
/// must carry a secret token: `--dashboard-token`, `--dashboard-token-file`, or
/// one the emulator draws and prints once as the dashboard URL with
/// `?token=...`. Viewing never needs it.
///
/// A request carries the token as "Authorization: Bearer TOKEN" or as the query
/// parameter `token=TOKEN` of its target (the WebSocket upgrade /ws?token=...,
/// which a browser cannot send headers with).
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace rfsitl::monitor {

/// Shortest and longest token accepted from the user. 16 characters of the
/// allowed alphabet are at least 96 bits when drawn at random.
inline constexpr std::size_t kMinControlTokenChars = 16;
inline constexpr std::size_t kMaxControlTokenChars = 256;

/// True when `bind_address` reaches this machine only: "localhost", 127.0.0.0/8,
/// ::1 or an IPv4-mapped 127.x address. An unspecified address (0.0.0.0, ::)
/// and every other address are reachable from elsewhere: false. Names other
/// than localhost are not resolved here: false.
bool bind_is_loopback(std::string_view bind_address);

/// Why `token` cannot be a control token, or "" when it can: 16 to 256
/// characters of A-Z a-z 0-9 . _ ~ - (they need no escaping in a URL or header).
std::string control_token_problem(std::string_view token);

/// 128 random bits read from /dev/urandom, as 32 lowercase hex digits. Throws
/// std::runtime_error when /dev/urandom cannot be read.
std::string generate_control_token();

/// True when `given` equals `expected`. The time taken depends only on the
/// lengths, never on where the first difference is, so that a client cannot
/// find the token one character at a time by timing refusals.
bool control_token_matches(std::string_view given, std::string_view expected);

/// The token a request carries: the "Authorization: Bearer TOKEN" header's
/// (scheme case-insensitive) if present, else the `token` query parameter of
/// `target` (percent-decoded); nullopt when it carries none.
std::optional<std::string> request_control_token(std::string_view target,
                                                 std::optional<std::string_view> authorization);

/// Why a control request must be refused, or "" to allow it. `expected` is the
/// dashboard's token; empty means none is required (loopback, none given).
std::string control_token_refusal(std::string_view target,
                                  std::optional<std::string_view> authorization,
                                  std::string_view expected);

}  // namespace rfsitl::monitor
