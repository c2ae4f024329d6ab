#pragma once
/// The MAVLink frame checksum. The MAVLink documents call it "X.25"; it is
/// CRC-16/MCRF4XX: polynomial 0x1021 processed reflected (0x8408), initial value
/// 0xFFFF, input and output reflected, no final XOR (true CRC-16/X-25 inverts
/// the result; MAVLink does not). Check value: "123456789" -> 0x6F91.
///
/// A frame's checksum covers every byte after the magic byte up to the end of
/// the payload as sent, then one more byte, the message's CRC_EXTRA (see
/// message_catalog.hpp), so that sender and receiver must agree on the message
/// layout. Header-only and constexpr; no state beyond the running value.
#include <cstdint>
#include <span>

namespace rfsitl::position::mavlink {

class Checksum {
 public:
  /// Folds one byte into the running value.
  constexpr void add(std::uint8_t byte) {
    // The byte-wise form of the reflected CRC: the low byte of the register
    // xor the input, spread back with the shifts that multiply by 0x1021
    // in the reflected domain (x^12 -> <<4 and >>4 halves, x^5 -> <<3).
    auto t = static_cast<std::uint8_t>(byte ^ (crc_ & 0xFFU));
    t = static_cast<std::uint8_t>(t ^ (t << 4));
    crc_ = static_cast<std::uint16_t>((crc_ >> 8) ^ (t << 8) ^ (t << 3) ^ (t >> 4));
  }

  constexpr void add(std::span<const std::uint8_t> bytes) {
    for (const std::uint8_t b : bytes) add(b);
  }

  constexpr std::uint16_t value() const { return crc_; }

 private:
  std::uint16_t crc_ = 0xFFFF;
};

/// The checksum of `bytes` followed by `crc_extra`: what a frame carries in its
/// two checksum bytes (low byte first) when `bytes` is the frame from its length
/// byte to the end of its payload.
constexpr std::uint16_t frame_checksum(std::span<const std::uint8_t> bytes,
                                       std::uint8_t crc_extra) {
  Checksum c;
  c.add(bytes);
  c.add(crc_extra);
  return c.value();
}

}  // namespace rfsitl::position::mavlink
