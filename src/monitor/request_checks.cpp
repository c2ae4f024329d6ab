#include "rfsitl/monitor/request_checks.hpp"

#include <utility>  // GCC 12 + C++20: before Boost.Asio

#include <algorithm>
#include <boost/asio/ip/address.hpp>
#include <cctype>
#include <charconv>

namespace rfsitl::monitor {
namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

struct HostParts {
  std::string_view name;
  std::optional<std::string_view> port;  // nullopt: absent; "" (after a colon): malformed
};

/// Splits "name[:port]" or "[v6][:port]"; nullopt when malformed.
std::optional<HostParts> split_host(std::string_view host) {
  std::string_view name = host;
  std::optional<std::string_view> port;
  if (host.starts_with('[')) {
    const auto close = host.find(']');
    if (close == std::string_view::npos) return std::nullopt;
    name = host.substr(0, close + 1);
    const std::string_view rest = host.substr(close + 1);
    if (!rest.empty()) {
      if (rest.front() != ':') return std::nullopt;
      port = rest.substr(1);
    }
  } else if (const auto colon = host.find(':'); colon != std::string_view::npos) {
    name = host.substr(0, colon);
    port = host.substr(colon + 1);
    if (port->find(':') != std::string_view::npos) return std::nullopt;  // unbracketed IPv6
  }
  if (name.empty()) return std::nullopt;
  return HostParts{name, port};
}

std::optional<std::uint16_t> parse_port(std::string_view s) {
  std::uint16_t v = 0;
  const auto res = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || res.ec != std::errc{} || res.ptr != s.data() + s.size()) return std::nullopt;
  return v;
}

/// "127.0.0.1" or "[::1]" as an address; nullopt for names.
std::optional<boost::asio::ip::address> ip_literal(std::string_view name) {
  boost::system::error_code ec;
  if (name.starts_with('[') && name.ends_with(']')) {
    const auto a =
        boost::asio::ip::make_address_v6(std::string(name.substr(1, name.size() - 2)), ec);
    if (!ec) return boost::asio::ip::address(a);
    return std::nullopt;
  }
  const auto a = boost::asio::ip::make_address_v4(std::string(name), ec);
  if (!ec) return boost::asio::ip::address(a);
  return std::nullopt;
}

bool name_allowed(std::string_view name, std::string_view bind_address) {
  if (lower(name) == "localhost") return true;
  const auto ip = ip_literal(name);
  if (!ip) return lower(name) == lower(bind_address);  // e.g. --bind localhost
  if (ip->is_loopback()) return true;
  boost::system::error_code ec;
  const auto bound = boost::asio::ip::make_address(std::string(bind_address), ec);
  if (ec) return false;
  // Bound to every address: any IP literal reaches it honestly.
  return bound.is_unspecified() || *ip == bound;
}

}  // namespace

bool host_allowed(std::string_view host, std::string_view bind_address, std::uint16_t port) {
  const auto parts = split_host(host);
  if (!parts) return false;
  if (parts->port && parse_port(*parts->port) != port) return false;
  return name_allowed(parts->name, bind_address);
}

bool origin_allowed(std::string_view origin, std::string_view bind_address, std::uint16_t port) {
  static constexpr std::string_view kScheme = "http://";
  if (origin.size() <= kScheme.size() || lower(origin.substr(0, kScheme.size())) != kScheme) {
    return false;
  }
  const auto parts = split_host(origin.substr(kScheme.size()));
  if (!parts) return false;
  const auto origin_port =
      parts->port ? parse_port(*parts->port) : std::optional<std::uint16_t>(80);
  return origin_port == port && name_allowed(parts->name, bind_address);
}

std::string request_refusal(std::optional<std::string_view> host,
                            std::optional<std::string_view> origin, std::string_view bind_address,
                            std::uint16_t port, bool& misdirected) {
  misdirected = true;
  if (!host) return "request without a Host header refused";
  if (!host_allowed(*host, bind_address, port)) {
    return "Host '" + std::string(*host) +
           "' is not this dashboard (use localhost, 127.0.0.1, [::1] or the bind address, port " +
           std::to_string(port) + "): refused to defeat DNS rebinding";
  }
  misdirected = false;
  if (origin && !origin_allowed(*origin, bind_address, port)) {
    return "cross-origin request from '" + std::string(*origin) +
           "' refused: only the dashboard's own page may use the API";
  }
  return "";
}

}  // namespace rfsitl::monitor
