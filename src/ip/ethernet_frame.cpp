#include "rfsitl/ip/ethernet_frame.hpp"

#include <algorithm>

namespace rfsitl::ip {

std::array<std::uint8_t, 6> node_mac(NodeId id) {
  return {0x02, 0x00, 0x00, 0x00, 0x00, id};
}

std::string_view verdict_name(EthernetVerdict v) {
  switch (v) {
    case EthernetVerdict::kUnicast:
      return "unicast";
    case EthernetVerdict::kBroadcast:
      return "broadcast";
    case EthernetVerdict::kTooShort:
      return "too_short";
    case EthernetVerdict::kTooLong:
      return "too_long";
    case EthernetVerdict::kNotIp:
      return "not_ip";
    case EthernetVerdict::kUnknownMac:
      return "unknown_mac";
    case EthernetVerdict::kToItself:
      return "to_itself";
    case EthernetVerdict::kForeignSource:
      return "foreign_source";
  }
  return "unknown";
}

Classified classify_ethernet(std::span<const std::uint8_t> frame, NodeId self,
                             const std::bitset<256>& nodes, std::size_t mtu) {
  Classified c;
  if (frame.size() < kEthernetHeaderBytes) return c;  // kTooShort
  c.ether_type = static_cast<std::uint16_t>(frame[12] << 8 | frame[13]);
  if (frame.size() > mtu + kEthernetHeaderBytes) {
    c.verdict = EthernetVerdict::kTooLong;
    return c;
  }
  if (c.ether_type != kEtherTypeIpv4 && c.ether_type != kEtherTypeIpv6 &&
      c.ether_type != kEtherTypeArp) {
    c.verdict = EthernetVerdict::kNotIp;
    return c;
  }
  // Our own interface sends with our MAC; anything else (a bridged or spoofed
  // source) would make receivers learn a neighbour that no radio answers for.
  const auto own = node_mac(self);
  if (!std::equal(own.begin(), own.end(), frame.begin() + 6)) {
    c.verdict = EthernetVerdict::kForeignSource;
    return c;
  }
  if ((frame[0] & 0x01) != 0) {  // the group bit: broadcast and every multicast
    c.verdict = EthernetVerdict::kBroadcast;
    c.dst = kBroadcastId;
    return c;
  }
  const auto prefix = node_mac(0);
  const NodeId id = frame[5];
  if (!std::equal(prefix.begin(), prefix.begin() + 5, frame.begin()) || !nodes.test(id)) {
    c.verdict = EthernetVerdict::kUnknownMac;
    return c;
  }
  if (id == self) {
    c.verdict = EthernetVerdict::kToItself;
    return c;
  }
  c.verdict = EthernetVerdict::kUnicast;
  c.dst = id;
  return c;
}

}  // namespace rfsitl::ip
