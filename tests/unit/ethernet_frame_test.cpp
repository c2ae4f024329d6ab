// What an IP node's TAP frames become: a radio destination or a refusal.
#include "rfsitl/ip/ethernet_frame.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace rfsitl::ip {
namespace {

std::vector<std::uint8_t> frame(std::array<std::uint8_t, 6> dst, NodeId src, std::uint16_t type,
                                std::size_t body = 46) {
  std::vector<std::uint8_t> f(dst.begin(), dst.end());
  const auto s = node_mac(src);
  f.insert(f.end(), s.begin(), s.end());
  f.push_back(static_cast<std::uint8_t>(type >> 8));
  f.push_back(static_cast<std::uint8_t>(type & 0xFF));
  f.resize(f.size() + body);
  return f;
}

std::bitset<256> ids(std::initializer_list<unsigned> list) {
  std::bitset<256> b;
  for (const unsigned i : list) b.set(i);
  return b;
}

TEST(EthernetFrame, UnicastGoesToTheNodeItsDestinationMacNames) {
  const auto c = classify_ethernet(frame(node_mac(3), 1, kEtherTypeIpv4), 1, ids({1, 2, 3}), 1500);
  EXPECT_EQ(c.verdict, EthernetVerdict::kUnicast);
  EXPECT_EQ(c.dst, 3);
  EXPECT_EQ(c.ether_type, kEtherTypeIpv4);
}

TEST(EthernetFrame, BroadcastAndMulticastBecomeRadioBroadcasts) {
  const std::array<std::uint8_t, 6> all{0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF};
  const std::array<std::uint8_t, 6> ipv6_all_nodes{0x33, 0x33, 0, 0, 0, 1};
  for (const auto& dst : {all, ipv6_all_nodes}) {
    const auto c = classify_ethernet(frame(dst, 2, kEtherTypeArp), 2, ids({1, 2}), 1500);
    EXPECT_EQ(c.verdict, EthernetVerdict::kBroadcast);
    EXPECT_EQ(c.dst, kBroadcastId);
  }
}

TEST(EthernetFrame, RefusalsNameTheirReason) {
  const auto nodes = ids({1, 2});
  EXPECT_EQ(classify_ethernet(std::vector<std::uint8_t>(13), 1, nodes, 1500).verdict,
            EthernetVerdict::kTooShort);
  EXPECT_EQ(classify_ethernet(frame(node_mac(2), 1, 0x88B5), 1, nodes, 1500).verdict,
            EthernetVerdict::kNotIp);
  EXPECT_EQ(classify_ethernet(frame(node_mac(2), 1, 0x8100), 1, nodes, 1500).verdict,
            EthernetVerdict::kNotIp);  // a VLAN tag
  EXPECT_EQ(classify_ethernet(frame(node_mac(9), 1, kEtherTypeIpv6), 1, nodes, 1500).verdict,
            EthernetVerdict::kUnknownMac);
  EXPECT_EQ(
      classify_ethernet(frame({0x04, 0, 0, 0, 0, 2}, 1, kEtherTypeIpv4), 1, nodes, 1500).verdict,
      EthernetVerdict::kUnknownMac);  // the last byte names a node, the rest is not ours
  EXPECT_EQ(classify_ethernet(frame(node_mac(1), 1, kEtherTypeIpv4), 1, nodes, 1500).verdict,
            EthernetVerdict::kToItself);
  EXPECT_EQ(classify_ethernet(frame(node_mac(2), 2, kEtherTypeIpv4), 1, nodes, 1500).verdict,
            EthernetVerdict::kForeignSource);
  // 1500 bytes of IP fit an MTU of 1500; one more does not.
  EXPECT_EQ(classify_ethernet(frame(node_mac(2), 1, kEtherTypeIpv4, 1500), 1, nodes, 1500).verdict,
            EthernetVerdict::kUnicast);
  EXPECT_EQ(classify_ethernet(frame(node_mac(2), 1, kEtherTypeIpv4, 1501), 1, nodes, 1500).verdict,
            EthernetVerdict::kTooLong);
  EXPECT_EQ(verdict_name(EthernetVerdict::kUnknownMac), "unknown_mac");
}

}  // namespace
}  // namespace rfsitl::ip
