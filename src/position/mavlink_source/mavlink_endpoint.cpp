#include "rfsitl/position/mavlink_source/mavlink_endpoint.hpp"

#include <charconv>

namespace rfsitl::position {
namespace {

constexpr std::string_view kForm = "tcp:HOST:PORT or udp:HOST:PORT, optionally +STEP";

// A decimal number in 0..max that fills all of `text`.
std::optional<std::uint32_t> number(std::string_view text, std::uint32_t max) {
  std::uint32_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || v > max) {
    return std::nullopt;
  }
  return v;
}

}  // namespace

std::optional<MavlinkEndpoint> MavlinkEndpoint::for_node(NodeId id) const {
  const std::uint32_t p = port + static_cast<std::uint32_t>(step) * (id - 1U);
  if (p > 65535U) return std::nullopt;
  MavlinkEndpoint e = *this;
  e.port = static_cast<std::uint16_t>(p);
  e.step = 0;
  return e;
}

std::string MavlinkEndpoint::text() const {
  std::string t = transport == MavlinkTransport::kTcpClient ? "tcp:" : "udp:";
  t += host.find(':') != std::string::npos ? "[" + host + "]" : host;
  t += ":" + std::to_string(port);
  if (step != 0) t += "+" + std::to_string(step);
  return t;
}

std::optional<MavlinkEndpoint> parse_mavlink_endpoint(std::string_view text, std::string& why) {
  const auto fail = [&](std::string_view detail) -> std::optional<MavlinkEndpoint> {
    why = "expected " + std::string(kForm) + ", got '" + std::string(text) + "'";
    if (!detail.empty()) why += " (" + std::string(detail) + ")";
    return std::nullopt;
  };
  MavlinkEndpoint e;
  std::string_view rest = text;
  if (rest.starts_with("tcp:")) {
    e.transport = MavlinkTransport::kTcpClient;
  } else if (rest.starts_with("udp:")) {
    e.transport = MavlinkTransport::kUdpListen;
  } else {
    return fail("unknown transport");
  }
  rest.remove_prefix(4);
  if (const auto plus = rest.rfind('+'); plus != std::string_view::npos) {
    const auto step = number(rest.substr(plus + 1), 65535);
    if (!step || *step == 0) return fail("STEP must be 1..65535");
    e.step = static_cast<std::uint16_t>(*step);
    rest = rest.substr(0, plus);
  }
  std::string_view host;
  if (rest.starts_with("[")) {
    const auto close = rest.find(']');
    if (close == std::string_view::npos || close + 1 >= rest.size() || rest[close + 1] != ':') {
      return fail("an IPv6 address goes in brackets: [::1]:PORT");
    }
    host = rest.substr(1, close - 1);
    rest.remove_prefix(close + 2);
  } else {
    const auto colon = rest.rfind(':');
    if (colon == std::string_view::npos) return fail("no port");
    host = rest.substr(0, colon);
    if (host.find(':') != std::string_view::npos) {
      return fail("an IPv6 address goes in brackets: [::1]:PORT");
    }
    rest.remove_prefix(colon + 1);
  }
  if (host.empty()) return fail("no host");
  const auto port = number(rest, 65535);
  if (!port || *port == 0) return fail("PORT must be 1..65535");
  e.host = std::string(host);
  e.port = static_cast<std::uint16_t>(*port);
  return e;
}

}  // namespace rfsitl::position
