/// IP nodes: classify_ethernet on any frame a program in a node's namespace
/// could write to its TAP interface.
///
/// Input: [1 byte: self id][32 bytes: the scenario's node ids as a bitmap]
/// [2 bytes: MTU][frame...]. Checks:
///  - a frame is accepted (unicast or broadcast) only if it is at least an
///    Ethernet header long, at most MTU + 14, IPv4, IPv6 or ARP, and from the
///    sending node's own MAC;
///  - a unicast destination is a node of the scenario other than the sender,
///    and its MAC names it; a broadcast one has the group bit set and the
///    radio destination is the broadcast id;
///  - the verdict has a name.
#include <bitset>
#include <cstddef>
#include <cstdint>
#include <span>

#include "fuzz_check.hpp"
#include "rfsitl/ip/ethernet_frame.hpp"

using namespace rfsitl;
using namespace rfsitl::ip;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 35) return 0;
  const NodeId self = data[0];
  std::bitset<256> nodes;
  for (std::size_t b = 0; b < 256; ++b) {
    if ((data[1 + b / 8] >> (b % 8)) & 1) nodes.set(b);
  }
  const std::size_t mtu = static_cast<std::size_t>(data[33]) << 8 | data[34];
  const std::span<const std::uint8_t> frame(data + 35, size - 35);
  const Classified c = classify_ethernet(frame, self, nodes, mtu);
  FUZZ_CHECK(!verdict_name(c.verdict).empty() && verdict_name(c.verdict) != "unknown",
             "verdict %d has no name", static_cast<int>(c.verdict));
  const bool accepted =
      c.verdict == EthernetVerdict::kUnicast || c.verdict == EthernetVerdict::kBroadcast;
  if (!accepted) return 0;
  FUZZ_CHECK(frame.size() >= kEthernetHeaderBytes && frame.size() <= mtu + kEthernetHeaderBytes,
             "accepted a frame of %zu bytes at MTU %zu", frame.size(), mtu);
  FUZZ_CHECK(c.ether_type == kEtherTypeIpv4 || c.ether_type == kEtherTypeIpv6 ||
                 c.ether_type == kEtherTypeArp,
             "accepted EtherType 0x%04x", c.ether_type);
  const auto own = node_mac(self);
  for (std::size_t k = 0; k < 6; ++k) {
    FUZZ_CHECK(frame[6 + k] == own[k], "accepted a source MAC other than node %u's", self);
  }
  if (c.verdict == EthernetVerdict::kBroadcast) {
    FUZZ_CHECK((frame[0] & 1) != 0 && c.dst == kBroadcastId, "broadcast without the group bit");
  } else {
    FUZZ_CHECK(c.dst != self && nodes.test(c.dst), "unicast to %u (self %u)", c.dst, self);
    const auto mac = node_mac(c.dst);
    for (std::size_t k = 0; k < 6; ++k) {
      FUZZ_CHECK(frame[k] == mac[k], "unicast to %u under another MAC", c.dst);
    }
  }
  return 0;
}
