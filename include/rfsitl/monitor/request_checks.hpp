#pragma once
/// Which requests the dashboard answers. A web page from another site, open in
/// the user's browser, can reach the dashboard in two ways, and both are refused:
///  - DNS rebinding: the attacker's name (evil.example) first resolves to the
///    attacker's server, then to 127.0.0.1; the browser then treats the
///    dashboard as evil.example's own. The browser still sends
///    "Host: evil.example:PORT", so the Host header must name this server.
///  - Cross-site requests (a form POST, a WebSocket): the browser sends the
///    page's Origin, which must be the dashboard's own page.
/// Clients that are not browsers (curl, scripts, Prometheus) send no Origin and
/// a Host naming the address they connected to, and pass.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace rfsitl::monitor {

/// True when `host` (the Host header: name or IP literal, then optionally
/// ":port") names this server: "localhost", a loopback IP literal
/// (127.0.0.1, [::1], ...), or the address it is bound to; with an unspecified
/// bind address (0.0.0.0, ::) any IP literal, since only a DNS name can be
/// rebound. Names compare case-insensitively. A port, if given, must be `port`.
bool host_allowed(std::string_view host, std::string_view bind_address, std::uint16_t port);

/// True when `origin` (the Origin header) is the dashboard's own page:
/// "http://" + a host that host_allowed accepts, on `port` (no port: 80).
/// "null", other schemes and other ports are refused.
bool origin_allowed(std::string_view origin, std::string_view bind_address, std::uint16_t port);

/// Why a request with these headers (nullopt: header absent) must be refused,
/// or "" to serve it. Host is required; Origin is checked when present. Sets
/// `misdirected` when the Host header is at fault (HTTP 421), else the Origin
/// is (403).
std::string request_refusal(std::optional<std::string_view> host,
                            std::optional<std::string_view> origin, std::string_view bind_address,
                            std::uint16_t port, bool& misdirected);

}  // namespace rfsitl::monitor
