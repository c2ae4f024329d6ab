#pragma once
/// The two checks of a DSSS frame: CRC-16 over the header and CRC-32 over the
/// payload. Own copies (not the OFDM module's) so the DSSS library stands alone.
#include <cstdint>
#include <span>

namespace rfsitl::phy::dsss {

/// CRC-16/CCITT-FALSE: polynomial 0x1021, initial value 0xFFFF, no reflection,
/// no final XOR (check value of "123456789": 0x29B1).
std::uint16_t crc16(std::span<const std::uint8_t> bytes);

/// CRC-32 of IEEE 802.3: reflected polynomial 0xEDB88320, initial value and
/// final XOR 0xFFFFFFFF (check value of "123456789": 0xCBF43926).
std::uint32_t crc32(std::span<const std::uint8_t> bytes);

}  // namespace rfsitl::phy::dsss
