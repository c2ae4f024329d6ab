#pragma once
/// The MAC frame check sequence: CRC-32 of IEEE 802.3 (reflected polynomial
/// 0xEDB88320, initial value and final XOR 0xFFFFFFFF), appended LSB first.
#include <cstdint>
#include <span>
#include <vector>

namespace rfsitl::phy::ofdm {

std::uint32_t crc32(std::span<const std::uint8_t> bytes);

/// `frame` followed by its 4-octet FCS.
std::vector<std::uint8_t> append_fcs(std::span<const std::uint8_t> frame);

/// True if the last 4 octets of `frame_with_fcs` are the FCS of the rest.
bool fcs_valid(std::span<const std::uint8_t> frame_with_fcs);

}  // namespace rfsitl::phy::ofdm
