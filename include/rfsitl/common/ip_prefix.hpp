#pragma once
/// IPv4 and IPv6 addresses with a prefix length: a network as a scenario
/// writes it ("10.77.0.0/24", "fd72:6673:6974:1::/64"), or an interface's
/// address in it ("10.77.0.2/24"); and the address of node `id` in a network:
/// the host part set to the id.
#include <arpa/inet.h>

#include <array>
#include <charconv>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "rfsitl/common/types.hpp"

namespace rfsitl {

struct Ipv4Prefix {
  std::array<std::uint8_t, 4> bytes{};
  unsigned length = 24;
};

struct Ipv6Prefix {
  std::array<std::uint8_t, 16> bytes{};
  unsigned length = 64;
};

namespace detail {

/// "ADDRESS/LENGTH" into its parts; nullopt without a slash or a number after it.
inline std::optional<std::pair<std::string, unsigned>> split_prefix(std::string_view text) {
  const auto slash = text.find('/');
  if (slash == std::string_view::npos) return std::nullopt;
  unsigned length = 0;
  const std::string_view digits = text.substr(slash + 1);
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), length);
  if (ec != std::errc{} || end != digits.data() + digits.size() || digits.empty()) {
    return std::nullopt;
  }
  return std::pair{std::string(text.substr(0, slash)), length};
}

/// "ADDRESS/LENGTH" of one family (AF_INET into Ipv4Prefix, AF_INET6 into
/// Ipv6Prefix), LENGTH at most the address's bits; nullopt otherwise.
template <typename Prefix, int Family>
std::optional<Prefix> parse_prefix(std::string_view text) {
  const auto parts = split_prefix(text);
  Prefix p;
  if (!parts || parts->second > 8 * p.bytes.size() ||
      inet_pton(Family, parts->first.c_str(), p.bytes.data()) != 1) {
    return std::nullopt;
  }
  p.length = parts->second;
  return p;
}

}  // namespace detail

/// "a.b.c.d/len" with len in 0..32; nullopt otherwise.
inline std::optional<Ipv4Prefix> parse_ipv4_prefix(std::string_view text) {
  return detail::parse_prefix<Ipv4Prefix, AF_INET>(text);
}

/// "x:y::/len" with len in 0..128; nullopt otherwise.
inline std::optional<Ipv6Prefix> parse_ipv6_prefix(std::string_view text) {
  return detail::parse_prefix<Ipv6Prefix, AF_INET6>(text);
}

/// Node `id`'s address: the prefix's network with the last byte set to the id
/// (precondition: length <= 24, so that the last byte is host part).
inline Ipv4Prefix node_address(const Ipv4Prefix& net, NodeId id) {
  Ipv4Prefix a = net;
  a.bytes[3] = id;
  return a;
}

/// Node `id`'s address: interface identifier ::id (precondition: length <= 120).
inline Ipv6Prefix node_address(const Ipv6Prefix& net, NodeId id) {
  Ipv6Prefix a = net;
  for (std::size_t i = 8; i < 15; ++i) a.bytes[i] = 0;
  a.bytes[15] = id;
  return a;
}

inline std::string to_string(const Ipv4Prefix& a) {
  char buf[INET_ADDRSTRLEN];
  inet_ntop(AF_INET, a.bytes.data(), buf, sizeof buf);
  return buf;
}

inline std::string to_string(const Ipv6Prefix& a) {
  char buf[INET6_ADDRSTRLEN];
  inet_ntop(AF_INET6, a.bytes.data(), buf, sizeof buf);
  return buf;
}

}  // namespace rfsitl
