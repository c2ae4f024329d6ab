#pragma once
/// The two checksums of the fast GMSK frame.
#include <cstdint>
#include <span>

namespace rfsitl::phy::gmsk {

/// CRC-16/CCITT-FALSE (polynomial 0x1021, initial value 0xFFFF, no reflection,
/// no final XOR); crc16("123456789") == 0x29B1. Protects the frame header.
std::uint16_t crc16(std::span<const std::uint8_t> bytes);

/// CRC-32 of IEEE 802.3 (reflected polynomial 0xEDB88320, initial value and final
/// XOR 0xFFFFFFFF); crc32("123456789") == 0xCBF43926. Protects the payload.
std::uint32_t crc32(std::span<const std::uint8_t> bytes);

}  // namespace rfsitl::phy::gmsk
