#pragma once
/// What the emulator does with an Ethernet frame a node's TAP interface hands
/// it: which radio destination its destination MAC names, or why it is
/// refused. Outside input (any program in the namespace can send any frame), so
/// it is a pure function with a fuzz target (fuzz/ethernet_frame_fuzzer.cpp).
///
/// Node n's MAC address is 02:00:00:00:00:n (locally administered, as the pcap
/// trace names nodes). A unicast frame goes to the node its destination MAC
/// names, the next hop, which need not be the packet's final destination (the
/// IP subnet is never looked at: routed prefixes are legitimate). Broadcast and
/// multicast frames (ARP, neighbour discovery, mDNS, a routing daemon's hellos)
/// become broadcast radio frames.
#include <array>
#include <bitset>
#include <cstdint>
#include <span>
#include <string_view>

#include "rfsitl/common/types.hpp"

namespace rfsitl::ip {

inline constexpr std::size_t kEthernetHeaderBytes = 14;
inline constexpr std::uint16_t kEtherTypeIpv4 = 0x0800;
inline constexpr std::uint16_t kEtherTypeArp = 0x0806;
inline constexpr std::uint16_t kEtherTypeIpv6 = 0x86DD;

/// 02:00:00:00:00:id.
std::array<std::uint8_t, 6> node_mac(NodeId id);

enum class EthernetVerdict : std::uint8_t {
  kUnicast,        ///< to the node `dst` names
  kBroadcast,      ///< broadcast or multicast: to every node in range
  kTooShort,       ///< shorter than an Ethernet header
  kTooLong,        ///< longer than the interface's MTU allows
  kNotIp,          ///< EtherType other than IPv4, IPv6 or ARP (VLAN tags included)
  kUnknownMac,     ///< a unicast destination that names no node of the scenario
  kToItself,       ///< a unicast destination that is the sending node itself
  kForeignSource,  ///< a source MAC other than the sending node's own
};

/// "not_ip", "unknown_mac", ... (log lines and counters).
std::string_view verdict_name(EthernetVerdict v);

struct Classified {
  EthernetVerdict verdict = EthernetVerdict::kTooShort;
  NodeId dst = 0;                ///< the radio destination (kBroadcastId for kBroadcast)
  std::uint16_t ether_type = 0;  ///< when the header was long enough
};

/// Classifies `frame` from node `self`'s interface. `nodes` has bit n set for
/// every node id n of the scenario; `mtu` is the interface's (IP bytes, without
/// the Ethernet header). Pure; any bytes are valid input.
Classified classify_ethernet(std::span<const std::uint8_t> frame, NodeId self,
                             const std::bitset<256>& nodes, std::size_t mtu);

}  // namespace rfsitl::ip
