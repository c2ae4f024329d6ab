#pragma once
/// The GFSK frame, in bits (one bit per symbol, most significant bit of each
/// octet first, as the Si4432 sends them; bit 1 is the upper tone, symbol +1):
///
///   preamble   8 p    p octets 0xAA (1010...), 2 <= p <= 64
///   sync       32     kSyncWord
///   header     80     the fast GMSK frame's header octets (src, dst, serial
///                     u32 LE, payload length u16 LE, CRC-16 of those 8), see
///                     src/phy/gmsk/frame_format.hpp
///   payload    8 n    the n payload octets
///   CRC        16     CRC-16 (rfsitl/common/crc.hpp) of the payload, high octet first
///
/// With whitening on, header, payload and CRC are XORed with the PN9 sequence
/// of gmsk::Whitener (restarted for every frame); preamble and sync never are.
#include <cstddef>
#include <cstdint>
#include <span>

#include "phy/gmsk/frame_format.hpp"
#include "rfsitl/phy/transceiver.hpp"

namespace rfsitl::phy::gfsk {

/// SiK's (and the Si4432's default) 0x2DD4, extended by 0xE395: among the
/// extensions, one of those whose 48 bits with the 16 preamble bits before
/// them differ in at least 13 places from every shift by 1..47 symbols (the
/// preamble before, unknown data after), so a whole-symbol timing error never
/// passes the receiver's 3-error tolerance.
inline constexpr std::uint32_t kSyncWord = 0x2DD4E395U;
inline constexpr std::size_t kSyncBits = 32;
inline constexpr std::uint8_t kPreambleOctet = 0xAA;
inline constexpr std::size_t kMinPreambleBytes = 2;
inline constexpr std::size_t kMaxPreambleBytes = 64;
inline constexpr std::size_t kHeaderBytes = gmsk::kHeaderBytes;
inline constexpr std::size_t kPayloadCrcBytes = 2;
inline constexpr std::size_t kMaxPayloadBytes = 65535;

/// The 48 bits the receiver looks for, oldest in bit 47: the last two
/// preamble octets and the sync word.
inline constexpr std::uint64_t kSyncPattern = (std::uint64_t{0xAAAA} << 32) | kSyncWord;
inline constexpr unsigned kSyncPatternBits = 48;

/// Bits (= symbols) of a frame.
constexpr std::size_t frame_bits(std::size_t preamble_bytes, std::size_t payload_bytes) {
  return 8 * (preamble_bytes + kSyncBits / 8 + kHeaderBytes + payload_bytes + kPayloadCrcBytes);
}

/// Writes the symbols (+1 or -1) of a frame to the front of `out` and returns
/// their number, frame_bits(preamble_bytes, payload.size()).
/// Preconditions: payload.size() <= kMaxPayloadBytes; out is long enough.
std::size_t build_frame_symbols(std::size_t preamble_bytes, bool whitening, const FrameTag& tag,
                                std::span<const std::uint8_t> payload, std::span<std::int8_t> out);

}  // namespace rfsitl::phy::gfsk
