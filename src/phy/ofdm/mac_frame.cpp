#include "mac_frame.hpp"

#include "fcs.hpp"

namespace rfsitl::phy::ofdm {
namespace {

constexpr std::uint8_t kLocalPrefix = 0x02;  // locally administered unicast MAC
constexpr std::uint8_t kSerialTag = 0x72;    // 'r': address 3 carries a serial

void put_node_address(std::vector<std::uint8_t>& out, NodeId id) {
  if (id == kBroadcastId) {
    out.insert(out.end(), 6, 0xFF);
    return;
  }
  out.insert(out.end(), {kLocalPrefix, 0, 0, 0, 0, id});
}

}  // namespace

std::vector<std::uint8_t> encode_mac_frame(const FrameTag& tag,
                                           std::span<const std::uint8_t> payload) {
  std::vector<std::uint8_t> f;
  f.reserve(kMacOverheadBytes + payload.size());
  f.insert(f.end(), {0x08, 0x00, 0x00, 0x00});
  put_node_address(f, tag.dst);
  put_node_address(f, tag.src);
  f.insert(f.end(), {kLocalPrefix, kSerialTag});
  for (int i = 0; i < 4; ++i) f.push_back(static_cast<std::uint8_t>(tag.serial >> (8 * i)));
  const auto seq = static_cast<std::uint16_t>((tag.serial & 0xFFFU) << 4);
  f.push_back(static_cast<std::uint8_t>(seq & 0xFF));
  f.push_back(static_cast<std::uint8_t>(seq >> 8));
  f.push_back(tag.src);
  f.push_back(tag.dst);
  f.insert(f.end(), payload.begin(), payload.end());
  return append_fcs(f);
}

std::optional<MacFrame> decode_mac_frame(std::span<const std::uint8_t> psdu) {
  if (psdu.size() < kMacOverheadBytes || psdu[0] != 0x08 || psdu[1] != 0x00 ||
      psdu[16] != kLocalPrefix || psdu[17] != kSerialTag) {
    return std::nullopt;
  }
  MacFrame m;
  m.tag.src = psdu[kMacHeaderBytes];
  m.tag.dst = psdu[kMacHeaderBytes + 1];
  for (int i = 0; i < 4; ++i) m.tag.serial |= static_cast<std::uint32_t>(psdu[18 + i]) << (8 * i);
  m.payload = psdu.subspan(kMacHeaderBytes + 2, psdu.size() - kMacOverheadBytes);
  return m;
}

}  // namespace rfsitl::phy::ofdm
